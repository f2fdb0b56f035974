"""ngincompat.resources: a process's peak memory."""

import subprocess
import sys


def test_the_peak_memory_is_this_process_own_and_grows_with_what_it_holds():
    """A fresh Python's peak is its own, tens of MiB (ru_maxrss would carry its parent's, the
    test runner's, with NGSolve loaded), and 200 MiB more held raises it by about that."""
    code = ("from ngincompat.resources import peak_mib; a = peak_mib(); "
            "b = bytearray(200 * 2**20); b[::4096] = b'x' * len(b[::4096]); "
            "print(a, peak_mib())")
    before, after = map(float, subprocess.run([sys.executable, "-c", code], check=True,
                                              capture_output=True, text=True).stdout.split())
    assert 0 < before < 100
    assert 190 < after - before < 230
