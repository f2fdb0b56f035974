"""A stand-in for the command line's main function, for tests/studies/test_corpus.py: its first
argument says what it does (the corpus's driver imports it by name)."""

import os
import signal
import sys
import time


def main(args):
    what = args[0]
    if what == "hang":
        time.sleep(600)
    if what == "slow":              # a long run that reports its progress
        for step in range(600):
            print(f"step {step}", file=sys.stderr)
            time.sleep(0.5)
    if what == "crash":
        os.kill(os.getpid(), signal.SIGSEGV)
    if what == "raise":
        raise RuntimeError("a bug")
    if what == "noise":             # as Netgen prints, past Python's sys.stdout
        os.write(1, b"{not a record\n")
        return 0
    if what == "exit":
        os._exit(7)
    return int(what)
