# SPDX-License-Identifier: MIT
"""A PNG's tEXt chunks: read them, and add one to a file. The README's pictures that a
browser draws carry what they were drawn from this way (tools/docs.py), since another
Chromium draws the same page in other bytes."""
import struct
import zlib

from .errors import ToolError

SIGNATURE = b"\x89PNG\r\n\x1a\n"


def chunks(data, where):
    """(type, body, offset of the chunk) of every chunk of a PNG's bytes."""
    if not data.startswith(SIGNATURE):
        raise ToolError("%s: not a PNG" % where)
    off, out = len(SIGNATURE), []
    while off + 12 <= len(data):
        length, kind = struct.unpack(">I4s", data[off:off + 8])
        end = off + 12 + length
        if end > len(data):
            break
        out.append((kind, data[off + 8:off + 8 + length], off))
        off = end
    if not out or out[-1][0] != b"IEND":
        raise ToolError("%s: a PNG cut short (no IEND at its end)" % where)
    return out


def read_text(path):
    """{keyword: text} of the PNG's tEXt chunks."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise ToolError("%s: cannot read: %s" % (path, e.strerror)) from None
    texts = {}
    for kind, body, _ in chunks(data, path):
        if kind == b"tEXt" and b"\0" in body:
            key, _, value = body.partition(b"\0")
            texts[key.decode("latin-1")] = value.decode("latin-1")
    return texts


def add_text(path, key, value):
    """Writes the PNG again with a tEXt chunk key=value just before its IEND."""
    with open(path, "rb") as f:
        data = f.read()
    iend = chunks(data, path)[-1][2]
    body = key.encode("latin-1") + b"\0" + value.encode("latin-1")
    chunk = struct.pack(">I", len(body)) + b"tEXt" + body
    chunk += struct.pack(">I", zlib.crc32(chunk[4:]))
    with open(path, "wb") as f:
        f.write(data[:iend] + chunk + data[iend:])
