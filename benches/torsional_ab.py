#!/usr/bin/env python3
"""A/B speed of `windrive bench torsional` between two commits, measured in one run.

Builds BASE (a commit, default HEAD~1) into its own worktree and target folder, packs its
torsional FMU, then runs the two binaries' `bench torsional` alternately (A B A B ...) so both see the
same machine state, and prints the ratio of their real-time factors (through FMI and without it),
the median over the rounds. Ratios above 1 mean the current tree is faster.

    python3 benches/torsional_ab.py                   # current tree against HEAD~1, 5 rounds
    python3 benches/torsional_ab.py --base 239c6f3 --rounds 9
    python3 benches/torsional_ab.py --loop --rounds 21 # the FMU's C symbols alone, as below

With --loop each round runs benches/torsional_loop.c (compiled here) on the two builds'
libtorsional.so instead: the bench's FMI loop (three inputs set, fmi2DoStep, the HSS torque read)
without the host's own code, its wall time per step, and its checksum, which says whether the two
builds compute the same bits. A round is short (LOOP_STEPS steps, about a third of a second), so many
rounds fit where this VM's phases would move a whole `bench torsional` run.

The current tree must be built and packed first (`cargo build --release && target/release/windrive
pack torsional`). The base build takes a few minutes on two cores; it is kept in target/ab-base.
"""

import argparse
import os
import re
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LINE = re.compile(r"^(FMU through FMI|same model, no FMI boundary)\S*\s.*?\s(\d+)\s+(\d+)\s")


def short(rev: str) -> str:
    """The abbreviated commit id of `rev`."""
    return subprocess.run(
        ["git", "-C", ROOT, "rev-parse", "--short", rev], capture_output=True, text=True, check=True
    ).stdout.strip()


def build_base(commit: str) -> tuple[str, str]:
    """Worktree of `commit` under target/ab-base/src, built into target/ab-base/target."""
    base = os.path.join(ROOT, "target", "ab-base")
    tree = os.path.join(base, "src")
    if os.path.isdir(tree):
        subprocess.run(["git", "-C", tree, "checkout", "--quiet", "--detach", commit], check=True)
    else:
        os.makedirs(base, exist_ok=True)
        subprocess.run(["git", "-C", ROOT, "worktree", "add", "--detach", tree, commit], check=True)
    env = dict(os.environ, CARGO_TARGET_DIR=os.path.join(base, "target"))
    subprocess.run(["cargo", "build", "--release", "--workspace"], cwd=tree, env=env, check=True)
    binary = os.path.join(base, "target", "release", "windrive")
    subprocess.run([binary, "pack", "torsional"], cwd=tree, env=env, check=True)
    fmu = os.path.join(base, "target", "fmu", "torsional.fmu")
    if not os.path.exists(fmu):  # older trees pack next to their own workspace
        fmu = os.path.join(tree, "target", "fmu", "torsional.fmu")
    return binary, fmu


LOOP_STEPS = 2_000_000


def compile_loop() -> str:
    exe = os.path.join(ROOT, "target", "torsional_loop")
    src = os.path.join(ROOT, "benches", "torsional_loop.c")
    subprocess.run(["cc", "-O2", "-o", exe, src, "-ldl"], check=True)
    return exe


def run_loop(exe: str, lib: str) -> tuple[str, float]:
    """The loop's checksum line and its wall time per step, ns."""
    out = subprocess.run([exe, lib, str(LOOP_STEPS)], capture_output=True, text=True, check=True).stdout
    checksum, timing = out.splitlines()[:2]
    return checksum, float(timing.split()[-1])


def loop_rounds(new_lib: str, base_lib: str, rounds: int, commit: str) -> None:
    exe = compile_loop()
    ratios, sums = [], set()
    for r in range(rounds):
        (sum_a, a), (sum_b, b) = run_loop(exe, new_lib), run_loop(exe, base_lib)
        sums.update([(sum_a, "current"), (sum_b, "base")])
        ratios.append(b / a)
        print(f"round {r + 1}/{rounds}: {a:.1f} vs {b:.1f} ns per step")
    same = len({s for s, _ in sums}) == 1
    print(f"\nspeed of the current tree's FMI loop over {commit} (median of {rounds} alternating rounds):")
    print(f"  {statistics.median(ratios):.3f}  (range {min(ratios):.3f}-{max(ratios):.3f})")
    print("  the same bits (checksums equal)" if same else f"  the results differ: {sorted(sums)}")


def run(binary: str, fmu: str) -> dict[str, float]:
    out = subprocess.run(
        [binary, "bench", "torsional", "--fmu", fmu], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout
    speeds = {}
    for line in out.splitlines():
        m = LINE.match(line)
        if m:
            speeds[m.group(1)] = float(m.group(2))
    if len(speeds) != 2:
        sys.exit(f"could not read the real-time factors from {binary}:\n{out}")
    return speeds


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--base", default="HEAD~1", help="commit to compare against (default HEAD~1)")
    p.add_argument("--rounds", type=int, default=5, help="A/B rounds (default 5)")
    p.add_argument("--base-binary", help="an already built base windrive (skips the build; with --base-fmu)")
    p.add_argument("--base-fmu", help="the base's torsional.fmu")
    p.add_argument("--loop", action="store_true", help="time benches/torsional_loop.c on the two libraries")
    p.add_argument("--base-lib", help="with --loop: an already built base libtorsional.so (skips the build)")
    args = p.parse_args()
    if args.loop:
        new_lib = os.path.join(ROOT, "target", "release", "libtorsional.so")
        if args.base_lib:
            commit, base_lib = args.base_lib, args.base_lib
        else:
            commit = short(args.base)
            base_lib = os.path.join(os.path.dirname(build_base(commit)[0]), "libtorsional.so")
        loop_rounds(new_lib, base_lib, args.rounds, commit)
        return
    if args.base_binary:
        commit, base_bin, base_fmu = args.base_binary, args.base_binary, args.base_fmu
    else:
        commit = short(args.base)
        base_bin, base_fmu = build_base(commit)
    new_bin = os.path.join(ROOT, "target", "release", "windrive")
    new_fmu = os.path.join(ROOT, "target", "fmu", "torsional.fmu")
    ratios: dict[str, list[float]] = {}
    for r in range(args.rounds):
        a = run(new_bin, new_fmu)
        b = run(base_bin, base_fmu)
        for k in a:
            ratios.setdefault(k, []).append(a[k] / b[k])
        print(f"round {r + 1}/{args.rounds}: " + ", ".join(f"{k}: {a[k]:.0f}x vs {b[k]:.0f}x real time" for k in a))
    print(f"\nspeed of the current tree over {commit} (median of {args.rounds} alternating rounds):")
    for k, v in ratios.items():
        print(f"  {k:<28} {statistics.median(v):.3f}  (range {min(v):.3f}-{max(v):.3f})")


if __name__ == "__main__":
    main()
