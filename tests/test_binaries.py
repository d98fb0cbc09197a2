"""The reader of libraries (``linkage_fmu.fmi.binaries``): a small library built for each
platform (gcc here, zig for the others) reads as its format and processor with exactly
the names it exports; universal Mach-O files are written as ``lipo`` writes them and
read back slice by slice; anything else is an error naming the file."""

from __future__ import annotations

import shutil
import struct
import subprocess
from pathlib import Path

import pytest

from linkage_fmu.ccompiler import compile_shared, find_compiler, find_cross_compiler
from linkage_fmu.fmi import binaries
from linkage_fmu.fmi.platforms import PLATFORMS, ZIG_FLAGS

#: one exported function, one hidden one, one static: only the first may be read
SOURCE = """
#ifdef _WIN32
#define EXPORT __declspec(dllexport)
#else
#define EXPORT __attribute__((visibility("default")))
#endif
static int kept_inside(int x) { return 2 * x; }
__attribute__((visibility("hidden"))) int hidden_one(int x) { return kept_inside(x) + 1; }
EXPORT int visible_one(int x) { return hidden_one(x) + 1; }
"""


def build(tmp_path: Path, platform: str | None) -> Path:
    """SOURCE as a library for ``platform`` (None: this machine, with its compiler)."""
    source = tmp_path / "lib.c"
    source.write_text(SOURCE)
    p = PLATFORMS[platform] if platform else None
    output = tmp_path / f"lib{p.suffix if p else '.so'}"
    return compile_shared([source], output, flags=("-O2", "-fvisibility=hidden",
                                                   *(p.flags + ZIG_FLAGS if p else ())),
                          target=p.zig if p else None)


@pytest.mark.skipif(find_compiler() is None, reason="no C compiler")
def test_a_library_of_this_machine(tmp_path):
    """gcc's library: ELF, shared, exporting visible_one only; an executable is not
    shared."""
    (s,) = binaries.read(build(tmp_path, None))
    assert (s.format, s.shared, s.exports) == ("elf", True, {"visible_one"})
    (exe,) = binaries.read(shutil.which("ls") or "/bin/ls")
    assert exe.format == "elf" and not exe.shared


@pytest.mark.skipif(find_cross_compiler() is None,
                    reason='zig is not installed (pip install "linkage-fmu[cross]")')
@pytest.mark.parametrize("platform", list(PLATFORMS))
def test_a_library_of_each_platform(tmp_path, platform):
    """zig's library for each platform reads as that platform's format and processor,
    exporting visible_one and (Mach-O) the linker's two symbols; where llvm-nm is
    installed, it lists the same names."""
    p = PLATFORMS[platform]
    library = build(tmp_path, platform)
    (s,) = binaries.read(library)
    assert (s.format, s.machine, s.shared) == (p.format, p.machine, True)
    linker = binaries.LINKER_MADE if p.format == "macho" else frozenset()
    assert s.exports == {"visible_one"} | linker
    assert binaries.problems(library, p.format, [p.machine], "visible", ["visible_one"]) == []
    nm = shutil.which("llvm-nm")
    if nm and p.format != "pe":
        listed = subprocess.run([nm, "-gU", "-D" if p.format == "elf" else "-g",
                                 str(library)], capture_output=True, text=True).stdout
        names = {line.split()[-1] for line in listed.splitlines() if line.strip()}
        assert {n[1:] if p.format == "macho" else n for n in names} == s.exports


def header(cpu: int, filetype: int = 6) -> bytes:
    """The 32 bytes of a 64-bit Mach-O header without load commands."""
    return struct.pack("<IiiIIIII", binaries.MACHO_MAGIC, cpu, 3 if cpu == 0x01000007 else 0,
                       filetype, 0, 0, 0, 0)


def test_universal_is_laid_out_as_lipo_does(tmp_path):
    """Big-endian fat header, slices at multiples of 16 kB in the order given, each with
    its CPU type and subtype and exact size; read back as two slices."""
    x86, arm = tmp_path / "x86", tmp_path / "arm"
    x86.write_bytes(header(0x01000007) + b"x" * 5000)
    arm.write_bytes(header(0x0100000C) + b"a" * 100)
    fat = binaries.universal([x86, arm], tmp_path / "fat").read_bytes()
    assert struct.unpack_from(">II", fat) == (binaries.FAT_MAGIC, 2)
    assert struct.unpack_from(">iiIII", fat, 8) == (0x01000007, 3, 16384, 5032, 14)
    assert struct.unpack_from(">iiIII", fat, 28) == (0x0100000C, 0, 32768, 132, 14)
    assert fat[16384:16384 + 5032] == x86.read_bytes()
    assert fat[32768:] == arm.read_bytes()
    assert [s.machine for s in binaries.read(tmp_path / "fat")] == ["x86_64", "aarch64"]


def test_bad_files_are_errors_naming_them(tmp_path):
    """Two slices of one processor, a thin file that is not Mach-O, a truncated ELF and
    text: each a BinaryError naming the file; problems() turns it into one sentence."""
    a, b, text = tmp_path / "a", tmp_path / "b", tmp_path / "text.dll"
    a.write_bytes(header(0x0100000C))
    b.write_bytes(header(0x0100000C))
    text.write_text("hello")
    with pytest.raises(binaries.BinaryError, match="same processor"):
        binaries.universal([a, b], tmp_path / "u")
    with pytest.raises(binaries.BinaryError, match="text.dll: not a thin 64-bit Mach-O"):
        binaries.universal([a, text], tmp_path / "u")
    truncated = tmp_path / "t.so"
    truncated.write_bytes(b"\x7fELF\x02\x01\x01" + bytes(20))
    with pytest.raises(binaries.BinaryError, match="t.so: malformed"):
        binaries.read(truncated)
    with pytest.raises(binaries.BinaryError, match="not an ELF, PE or Mach-O file"):
        binaries.read(text)
    assert binaries.problems(text, "pe", ["x86_64"], "fmi2") == [
        f"{text}: not an ELF, PE or Mach-O file (it starts with b'hello')"]
    (s,) = binaries.read(a)
    assert binaries.problems(a, "macho", ["aarch64", "x86_64"], "fmi2") == [
        "1 slice(s) where 2 were expected"] and s.exports == frozenset()
