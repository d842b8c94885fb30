"""The C compiler CasADi's JIT calls (`_cc_cache.py --cache=DIR FLAGS -c SOURCE.c -o OBJECT.o`), with a cache.

CasADi writes the same C source for the same expression, so an object is kept under the hash of its source,
flags and compiler; a second process that builds the same transcription links the kept object instead of
compiling ~3 MB of derivative code again (about 45 s at -O1 for the L/D 1.89 tables). It is the linker too
(`_cc_cache.py --cache=DIR OBJECT.o -o LIBRARY.so -shared`): the shared library is kept under the hash of its
object, so a second process calls no compiler at all (the five links of the L/D 1.89 transcription took 1 s).
A plain script: it runs in its own process, started by CasADi through the shell. $CC (default gcc) compiles.
"""

import hashlib
import os
import shutil
import subprocess
import sys
import tempfile


def main(args: list[str]) -> int:
    folder = args.pop(0).removeprefix("--cache=")
    compiler = os.environ.get("CC", "gcc")
    output = args[args.index("-o") + 1]
    # the input: the C source when compiling, the object when linking (kept as ".o" and ".so" respectively)
    source = next((a for a in args if a.endswith(".c")), None)
    suffix = ".o" if source is not None else ".so"
    if source is None:
        source = next(a for a in args if a.endswith(".o"))
    digest = hashlib.sha256()
    with open(source, "rb") as f:
        digest.update(f.read())
    digest.update(" ".join([compiler] + [a for a in args if a not in (source, output)]).encode())
    kept = os.path.join(folder, digest.hexdigest()[:32] + suffix)
    if os.path.exists(kept):
        shutil.copyfile(kept, output)
        return 0
    code = subprocess.call([compiler] + args)
    if code == 0:
        os.makedirs(folder, exist_ok=True)
        fd, partial = tempfile.mkstemp(dir=folder, suffix=".part")
        os.close(fd)
        shutil.copyfile(output, partial)
        os.replace(partial, kept)  # atomic: a concurrent build sees the whole object or none
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
