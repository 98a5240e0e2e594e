"""Compile profile: what each kernel costs to compile on the first run of a command.

Runs ``periodyn ARGS...`` in this process with a recorder on Numba's ``numba:compile``
events and prints, per kernel module (family) and per function, the compile time in CPU
seconds of this process (the machine may be loaded; compiling is single-threaded)
exclusive of the callees compiled inside it, and the number of type specializations
(signatures) each function got, then the process CPU and wall seconds. Use a cold cache
to see first-install costs:

    NUMBA_CACHE_DIR=$(mktemp -d) python benchmarks/compile_profile.py sweep \
        sweeps/slider_crank_elements.toml --omega 200:201:2 --out /tmp/x.nc --workers 1

``--top N`` functions are listed (default 25); ``--signatures`` lists each signature.
"""

import argparse
import os
import time
from collections import defaultdict

from numba.core import event


class _Profile(event.Listener):
    """Exclusive compile CPU seconds per (module, function), one entry per signature."""

    def __init__(self):
        self.stack = []  # [start, child seconds, key, signature]
        self.seconds = defaultdict(float)
        self.signatures = defaultdict(list)
        self.top = defaultdict(float)  # module -> CPU s of its outermost compiles, callees included

    def on_start(self, ev):
        disp = ev.data["dispatcher"]
        key = (disp.py_func.__module__, disp.py_func.__qualname__)
        self.stack.append([time.process_time(), 0.0, key, tuple(ev.data["args"])])

    def on_end(self, ev):
        start, children, key, sig = self.stack.pop()
        total = time.process_time() - start
        self.seconds[key] += total - children
        self.signatures[key].append(sig)
        if self.stack:
            self.stack[-1][1] += total
        else:
            self.top[key[0]] += total


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--top", type=int, default=25)
    ap.add_argument("--signatures", action="store_true")
    args, rest = ap.parse_known_args()
    from periodyn.cli import main as cli_main

    profile = _Profile()
    wall0, cpu0 = time.perf_counter(), time.process_time()
    with event.install_listener("numba:compile", profile):
        cli_main(rest)
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    families = defaultdict(lambda: [0.0, 0, 0])
    for (module, name), s in profile.seconds.items():
        fam = families[module.replace("periodyn.kernels.", "")]
        fam[0] += s
        fam[1] += 1
        fam[2] += len(profile.signatures[(module, name)])
    total = sum(profile.seconds.values())
    print(f"\ncompile profile of `periodyn {' '.join(rest)}`  (NUMBA_CACHE_DIR={os.environ.get('NUMBA_CACHE_DIR', '-')})")
    print(f"{'family (module)':<36}{'CPU s':>10}{'functions':>10}{'signatures':>11}")
    for module, (s, nf, ns) in sorted(families.items(), key=lambda kv: -kv[1][0]):
        print(f"{module:<36}{s:10.1f}{nf:10d}{ns:11d}")
    print(f"{'total':<36}{total:10.1f}{len(profile.seconds):10d}{sum(len(v) for v in profile.signatures.values()):11d}")
    print(f"\n{'outermost compiles by module (callees included: what a first run waits for)':<80}")
    for module, s in sorted(profile.top.items(), key=lambda kv: -kv[1]):
        print(f"  {module.replace('periodyn.kernels.', ''):<34}{s:10.1f}")
    print(f"\n{'function':<60}{'CPU s':>10}{'signatures':>11}")
    for key, s in sorted(profile.seconds.items(), key=lambda kv: -kv[1])[: args.top]:
        print(f"{key[0].replace('periodyn.kernels.', '') + '.' + key[1]:<60}{s:10.1f}{len(profile.signatures[key]):11d}")
        if args.signatures:
            for sig in profile.signatures[key]:
                print(f"      {sig}")
    print(f"\nprocess: {cpu:.1f} s CPU, {wall:.1f} s wall (compile events {total:.1f} s CPU)")


if __name__ == "__main__":
    main()
