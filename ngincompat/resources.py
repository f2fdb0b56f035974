"""What a process has used: its peak memory."""

import resource


def peak_mib() -> float:
    """Peak resident set size of this process so far [MiB].

    Linux's ``VmHWM`` (/proc/self/status) belongs to the process image: ru_maxrss is not
    reset by exec and so carries the peak of the process that spawned this one (under pytest,
    over a GiB). ``ru_maxrss`` is the fallback where /proc is missing.
    """
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
