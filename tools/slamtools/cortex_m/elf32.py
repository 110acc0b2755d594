# SPDX-License-Identifier: MIT
"""A minimal reader of 32-bit little-endian ELF files: loadable segments and symbols.

Enough for the Cortex-M tools to load an image into an emulator and find functions by
name, without third-party modules. A file that is missing, not such an ELF file or cut
short is a ToolError naming it.
"""
import struct

from ..errors import ToolError


class Elf:
    def __init__(self, path):
        try:
            with open(path, "rb") as f:
                self.data = f.read()
        except OSError as e:
            raise ToolError("%s: cannot read: %s" % (path, e.strerror)) from None
        if self.data[:4] != b"\x7fELF" or self.data[4:6] != b"\x01\x01":
            raise ToolError("%s: not a 32-bit little-endian ELF file" % path)
        try:
            self._read()
        except (struct.error, IndexError, ValueError, UnicodeDecodeError):
            # An offset or a name beyond the file: what a truncated or corrupted image gives.
            raise ToolError("%s: a malformed ELF file (cut short?)" % path) from None

    def _read(self):
        d = self.data
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
            raise ToolError("symbol %s is not in the image" % name)
        return self.symbols[name][0]

    def functions(self, prefix=""):
        """(name, start, end) of every function whose name starts with prefix."""
        return [(n, v[0], v[0] + v[1]) for n, v in self.symbols.items()
                if v[2] == 2 and n.startswith(prefix)]
