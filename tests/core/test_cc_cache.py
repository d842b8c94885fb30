"""core/_cc_cache.py, the compiler and linker CasADi's JIT calls: a second build of the same source calls no compiler
(issue 29: "no gcc in a second run"), and what it hands back works."""

import ctypes
import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest

import footprint.core._cc_cache as cc_cache

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None, reason="no C compiler on this machine")
SCRIPT = Path(cc_cache.__file__)


def cc(tmp_path, *args):
    """The script as CasADi runs it, with $CC a gcc that writes each call to calls.log."""
    wrapper = tmp_path / "gcc-logged"
    wrapper.write_text(f'#!/bin/sh\necho "$@" >> {tmp_path / "calls.log"}\nexec gcc "$@"\n')
    wrapper.chmod(wrapper.stat().st_mode | stat.S_IEXEC)
    env = dict(os.environ, CC=str(wrapper))
    return subprocess.run([sys.executable, str(SCRIPT), f"--cache={tmp_path / 'kept'}", *args], env=env).returncode


def calls(tmp_path):
    log = tmp_path / "calls.log"
    return log.read_text().splitlines() if log.exists() else []


def test_a_second_compile_and_link_of_the_same_source_call_no_compiler(tmp_path):
    for build in ("first", "second"):  # CasADi names its temporary files anew each time
        folder = tmp_path / build
        folder.mkdir()
        (folder / "f.c").write_text("double twice(double x) { return 2.0 * x; }\n")
        assert cc(tmp_path, "-O1", "-fPIC", "-c", str(folder / "f.c"), "-o", str(folder / "f.o")) == 0
        assert cc(tmp_path, str(folder / "f.o"), "-o", str(folder / "f.so"), "-shared") == 0
        library = ctypes.CDLL(str(folder / "f.so"))
        library.twice.restype, library.twice.argtypes = ctypes.c_double, [ctypes.c_double]
        assert library.twice(21.0) == 42.0  # what came back, built or kept, is the function
    # the first build compiled and linked; the second took both from the cache
    assert len(calls(tmp_path)) == 2 and "-c" in calls(tmp_path)[0] and "-shared" in calls(tmp_path)[1]
    assert (tmp_path / "first" / "f.so").read_bytes() == (tmp_path / "second" / "f.so").read_bytes()


def test_a_changed_source_is_compiled_again(tmp_path):
    for body in ("2.0 * x", "3.0 * x"):
        (tmp_path / "f.c").write_text(f"double f(double x) {{ return {body}; }}\n")
        assert cc(tmp_path, "-fPIC", "-c", str(tmp_path / "f.c"), "-o", str(tmp_path / "f.o")) == 0
    assert len(calls(tmp_path)) == 2


def test_a_failed_compile_keeps_nothing(tmp_path):
    (tmp_path / "bad.c").write_text("this is not C\n")
    assert cc(tmp_path, "-c", str(tmp_path / "bad.c"), "-o", str(tmp_path / "bad.o")) != 0
    assert not list((tmp_path / "kept").glob("*.o"))
