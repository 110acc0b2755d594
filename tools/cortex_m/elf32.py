# SPDX-License-Identifier: MIT
"""A minimal reader of 32-bit little-endian ELF files: loadable segments and symbols.

Enough for the Cortex-M tools to load an image into an emulator and find functions by
name, without third-party modules.
"""
import struct


class Elf:
    def __init__(self, path):
        with open(path, "rb") as f:
            self.data = f.read()
        d = self.data
        if d[:4] != b"\x7fELF" or d[4] != 1 or d[5] != 1:
            raise ValueError("%s: not a 32-bit little-endian ELF file" % path)
        (self.entry, phoff, shoff, _flags, _ehsize, phentsize, phnum, shentsize, shnum,
         shstrndx) = struct.unpack_from("<IIIIHHHHHH", d, 24)
        self.segments = []  # (vaddr, paddr, file bytes, memsz) of PT_LOAD
        for i in range(phnum):
            p_type, p_offset, p_vaddr, p_paddr, p_filesz, p_memsz = struct.unpack_from(
                "<IIIIII", d, phoff + i * phentsize)
            if p_type == 1:
                self.segments.append((p_vaddr, p_paddr, d[p_offset:p_offset + p_filesz], p_memsz))
        self.sections = []
        for i in range(shnum):
            self.sections.append(struct.unpack_from("<IIIIIIIIII", d, shoff + i * shentsize))
        self.symbols = {}  # name -> (address, size, type, bind); functions keep the Thumb bit off
        self.local_functions = set()  # names of static (local) functions
        for sh in self.sections:
            if sh[1] != 2:  # SHT_SYMTAB
                continue
            strtab = self.sections[sh[6]]
            for off in range(sh[4], sh[4] + sh[5], 16):
                st_name, value, size, info, _other, shndx = struct.unpack_from("<IIIBBH", d, off)
                if st_name == 0 or shndx == 0:
                    continue
                end = d.index(b"\0", strtab[4] + st_name)
                name = d[strtab[4] + st_name:end].decode()
                typ = info & 0xF
                if typ == 2:  # STT_FUNC
                    value &= ~1
                    if info >> 4 == 0:
                        self.local_functions.add(name)
                if name not in self.symbols or (info >> 4) == 1:  # globals win over locals
                    self.symbols[name] = (value, size, typ, info >> 4)

    def addr(self, name):
        if name not in self.symbols:
            raise KeyError("symbol %s is not in the image" % name)
        return self.symbols[name][0]

    def functions(self, prefix=""):
        """(name, start, end) of every function whose name starts with prefix."""
        return [(n, v[0], v[0] + v[1]) for n, v in self.symbols.items()
                if v[2] == 2 and n.startswith(prefix)]
