"""What a shared library is, read from its bytes: its format (ELF, PE or Mach-O, thin or
universal), processor, and the names it exports; and the universal Mach-O of several
thin ones, as ``lipo -create`` writes it. Enough of each format to check an FMU's
binaries on any machine, with no tool of the platform.

- ELF: the dynamic symbols (``.dynsym``) that are defined, global or weak, and of default
  or protected visibility: what the dynamic loader binds.
- PE: the names of the export table.
- Mach-O: the names of the export trie (what dyld binds), without the leading ``_`` that
  C names get. zig's linker adds two symbols of its own to every dylib,
  ``__mh_dylib_header`` and ``___dso_handle`` (data, not functions; :data:`LINKER_MADE`).

Examples
--------
>>> import tempfile
>>> from pathlib import Path
>>> with tempfile.TemporaryDirectory() as tmp:
...     path = Path(tmp) / "x.so"
...     _ = path.write_bytes(b"not a library")
...     try:
...         read(path)
...     except BinaryError as err:
...         print(str(err).split(": ", 1)[1])
not an ELF, PE or Mach-O file (it starts with b'not a li')
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ..errors import LinkageFmuError

#: what zig's Mach-O linker exports from every dylib besides the code's own names
LINKER_MADE = frozenset({"_mh_dylib_header", "__dso_handle"})

ELF_MACHINES = {62: "x86_64", 183: "aarch64"}
PE_MACHINES = {0x8664: "x86_64", 0xAA64: "aarch64"}
MACHO_MACHINES = {0x01000007: "x86_64", 0x0100000C: "aarch64"}
FAT_MAGIC, MACHO_MAGIC = 0xCAFEBABE, 0xFEEDFACF
#: slices of a universal binary start at multiples of 2**FAT_ALIGN (arm64's page: 16 kB)
FAT_ALIGN = 14


class BinaryError(LinkageFmuError, ValueError):
    """A file that is not a library of the formats read here, or is malformed."""


@dataclass(frozen=True)
class Slice:
    """One library: its format, processor, whether it is a shared library (not an
    executable), and the names it exports."""

    format: str
    machine: str
    shared: bool
    exports: frozenset[str]


def read(path: str | Path) -> tuple[Slice, ...]:
    """The library at ``path``: one slice, or one per architecture of a universal Mach-O.

    Raises
    ------
    BinaryError
        Not an ELF (64-bit, little-endian), PE32+ or 64-bit Mach-O file, or malformed.
    """
    data = Path(path).read_bytes()
    try:
        if data[:4] == b"\x7fELF":
            return (_elf(data),)
        if data[:2] == b"MZ":
            return (_pe(data),)
        if len(data) >= 4 and struct.unpack_from(">I", data)[0] == FAT_MAGIC:
            n = struct.unpack_from(">I", data, 4)[0]
            slices = []
            for k in range(n):
                _, _, offset, size, _ = struct.unpack_from(">iiIII", data, 8 + 20 * k)
                slices.append(_macho(data[offset:offset + size]))
            return tuple(slices)
        if len(data) >= 4 and struct.unpack_from("<I", data)[0] == MACHO_MAGIC:
            return (_macho(data),)
    except (struct.error, IndexError, KeyError, UnicodeDecodeError) as err:
        raise BinaryError(f"{path}: malformed ({type(err).__name__}: {err})") from None
    raise BinaryError(f"{path}: not an ELF, PE or Mach-O file (it starts with {data[:8]!r})")


def _cstring(data: bytes, offset: int) -> str:
    return data[offset:data.index(b"\0", offset)].decode("ascii")


def _elf(data: bytes) -> Slice:
    if data[4] != 2 or data[5] != 1:
        raise BinaryError("only 64-bit little-endian ELF is read")
    e_type, e_machine = struct.unpack_from("<HH", data, 16)
    shoff = struct.unpack_from("<Q", data, 0x28)[0]
    shentsize, shnum = struct.unpack_from("<HH", data, 0x3A)
    sections = [struct.unpack_from("<IIQQQQIIQQ", data, shoff + k * shentsize)
                for k in range(shnum)]
    exports = set()
    for _, sh_type, _, _, offset, size, link, _, _, entsize in sections:
        if sh_type != 11:  # SHT_DYNSYM
            continue
        strings = sections[link][4]
        for at in range(offset + entsize, offset + size, entsize):  # entry 0 is null
            name, info, other, shndx = struct.unpack_from("<IBBH", data, at)
            if shndx != 0 and info >> 4 in (1, 2) and other & 3 in (0, 3):
                exports.add(_cstring(data, strings + name))
    phoff = struct.unpack_from("<Q", data, 0x20)[0]
    phentsize, phnum = struct.unpack_from("<HH", data, 0x36)
    interpreter = any(struct.unpack_from("<I", data, phoff + k * phentsize)[0] == 3
                      for k in range(phnum))  # PT_INTERP: a program (PIE is ET_DYN too)
    return Slice("elf", ELF_MACHINES.get(e_machine, f"elf machine {e_machine}"),
                 e_type == 3 and not interpreter, frozenset(exports))


def _pe(data: bytes) -> Slice:
    at = struct.unpack_from("<I", data, 0x3C)[0]
    if data[at:at + 4] != b"PE\0\0":
        raise BinaryError("an MZ file without a PE header")
    machine, nsections, _, _, _, optional_size, characteristics = struct.unpack_from(
        "<HHIIIHH", data, at + 4)
    optional = at + 24
    if struct.unpack_from("<H", data, optional)[0] != 0x20B:
        raise BinaryError("only PE32+ (64-bit) is read")
    sections = [struct.unpack_from("<8sIIII", data, optional + optional_size + 40 * k)
                for k in range(nsections)]

    def offset(rva: int) -> int:
        for _, vsize, va, raw_size, raw in sections:
            if va <= rva < va + max(vsize, raw_size):
                return rva - va + raw
        raise BinaryError(f"address {rva:#x} is in no section")

    exports = set()
    export_rva, export_size = struct.unpack_from("<II", data, optional + 112)
    if export_size:
        directory = offset(export_rva)
        n_functions, n_names, _, names = struct.unpack_from("<IIII", data, directory + 20)
        for k in range(n_names):
            exports.add(_cstring(data, offset(struct.unpack_from("<I", data,
                                                                  offset(names) + 4 * k)[0])))
        exports.update(f"<ordinal {k}>" for k in range(n_functions - n_names))
    return Slice("pe", PE_MACHINES.get(machine, f"pe machine {machine:#x}"),
                 bool(characteristics & 0x2000), frozenset(exports))


def _uleb(data: bytes, at: int) -> tuple[int, int]:
    value = shift = 0
    while True:
        byte = data[at]
        at += 1
        value |= (byte & 0x7F) << shift
        shift += 7
        if byte < 0x80:
            return value, at


def _trie(data: bytes, start: int, node: int, prefix: str, out: set, depth: int = 0) -> None:
    if depth > 4096:
        raise BinaryError("the export trie is too deep")
    size, at = _uleb(data, start + node)
    if size:
        out.add(prefix)
    at += size
    children, at = data[at], at + 1
    for _ in range(children):
        end = data.index(b"\0", at)
        label = data[at:end].decode("ascii")
        child, at = _uleb(data, end + 1)
        _trie(data, start, child, prefix + label, out, depth + 1)


def _macho(data: bytes) -> Slice:
    magic, cputype, _, filetype, ncmds = struct.unpack_from("<IiiII", data)
    if magic != MACHO_MAGIC:
        raise BinaryError("only 64-bit little-endian Mach-O is read")
    names: set[str] = set()
    at = 32
    for _ in range(ncmds):
        cmd, size = struct.unpack_from("<II", data, at)
        if cmd == 0x80000022:  # LC_DYLD_INFO_ONLY: the trie's offset and size at 40, 44
            trie, trie_size = struct.unpack_from("<II", data, at + 40)
        elif cmd == 0x80000033:  # LC_DYLD_EXPORTS_TRIE
            trie, trie_size = struct.unpack_from("<II", data, at + 8)
        else:
            trie_size = 0
        if trie_size:
            _trie(data, trie, 0, "", names)
        at += size
    exports = frozenset(n[1:] if n.startswith("_") else n for n in names)
    return Slice("macho", MACHO_MACHINES.get(cputype & 0xFFFFFFFF, f"cpu type {cputype:#x}"),
                 filetype == 6, exports)


def universal(thin: Sequence[str | Path], out: str | Path) -> Path:
    """Write ``out``, the universal Mach-O holding the ``thin`` ones (one per processor),
    and return its path.

    Raises
    ------
    BinaryError
        A file is not a thin 64-bit Mach-O, or two are for the same processor.

    Examples
    --------
    >>> import tempfile
    >>> header = lambda cpu: struct.pack("<IiiIIIII", MACHO_MAGIC, cpu, 0, 6, 0, 0, 0, 0)
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     a, b = Path(tmp) / "a", Path(tmp) / "b"
    ...     _ = a.write_bytes(header(0x01000007)), b.write_bytes(header(0x0100000C))
    ...     [(s.format, s.machine, s.shared) for s in read(universal([a, b], Path(tmp) / "u"))]
    [('macho', 'x86_64', True), ('macho', 'aarch64', True)]
    """
    blobs = [Path(p).read_bytes() for p in thin]
    heads = []
    for path, blob in zip(thin, blobs):
        if len(blob) < 32 or struct.unpack_from("<I", blob)[0] != MACHO_MAGIC:
            raise BinaryError(f"{path}: not a thin 64-bit Mach-O file")
        heads.append(struct.unpack_from("<ii", blob, 4))
    if len({cpu for cpu, _ in heads}) != len(heads):
        raise BinaryError("two of the thin files are for the same processor")
    align = 1 << FAT_ALIGN
    header = bytearray(struct.pack(">II", FAT_MAGIC, len(blobs)))
    offset, body = align, bytearray()
    for (cpu, subtype), blob in zip(heads, blobs):
        body += bytes(offset - align - len(body))  # the previous slice padded to `align`
        header += struct.pack(">iiIII", cpu, subtype, offset, len(blob), FAT_ALIGN)
        body += blob
        offset += len(blob) + (-len(blob) % align)
    out = Path(out)
    out.write_bytes(bytes(header) + bytes(align - len(header)) + bytes(body))
    return out


def problems(path: str | Path, format: str, machines: Sequence[str], prefix: str,
             required: Sequence[str] = ()) -> list[str]:
    """What is wrong with ``path`` as a shared library of ``format`` for ``machines`` (one
    slice each, in order) that exports the names ``required`` and no name that does not
    start with ``prefix`` (but :data:`LINKER_MADE` in a Mach-O): one sentence each, none
    if it is right.

    Examples
    --------
    >>> import tempfile
    >>> header = struct.pack("<IiiIIIII", MACHO_MAGIC, 0x0100000C, 0, 6, 0, 0, 0, 0)
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     _ = (Path(tmp) / "a.dylib").write_bytes(header)
    ...     problems(Path(tmp) / "a.dylib", "macho", ["x86_64"], "fmi2", ["fmi2DoStep"])
    ['a slice for aarch64 where one for x86_64 was expected', 'fmi2DoStep is not exported']
    """
    try:
        slices = read(path)
    except BinaryError as err:
        return [str(err)]
    found = []
    if len(slices) != len(machines):
        found.append(f"{len(slices)} slice(s) where {len(machines)} were expected")
    for s, machine in zip(slices, machines):
        if s.format != format:
            found.append(f"a {s.format} file where {format} was expected")
        if s.machine != machine:
            found.append(f"a slice for {s.machine} where one for {machine} was expected")
        if not s.shared:
            found.append("an executable, not a shared library")
        allowed = LINKER_MADE if s.format == "macho" else frozenset()
        stray = sorted(n for n in s.exports - allowed if not n.startswith(prefix))
        if stray:
            found.append(f"exports names that are not {prefix}*: {', '.join(stray[:10])}")
        found += [f"{n} is not exported" for n in required if n not in s.exports]
    return list(dict.fromkeys(found))
