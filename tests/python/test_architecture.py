"""The layering of src/ (ARCHITECTURE.md): each layer imports only what its table allows, a command
file never imports from the dispatcher, and no two Rust files import each other, directly or round a
longer loop. A module's imports are every `crate::`, `super::` and `self::` path outside comments and
unit-test modules, resolved to the deepest module file that exists; a `mod.rs` re-exporting its
children (`pub use`) is a facade, not a dependency."""

import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
SRC = ROOT / "src"


def modpath(f: pathlib.Path) -> tuple[str, ...]:
    parts = list(f.relative_to(SRC).with_suffix("").parts)
    if parts[-1] in ("mod", "lib", "main"):
        parts = parts[:-1]
    return tuple(parts)


def import_graph() -> dict[tuple[str, ...], set[tuple[str, ...]]]:
    files = {modpath(f): f for f in SRC.rglob("*.rs")}

    def resolve(parts):
        for k in range(len(parts), -1, -1):
            if tuple(parts[:k]) in files:
                return tuple(parts[:k])
        return None

    def base_of(m, segs, is_mod):
        if segs[0] == "crate":
            return [], segs[1:]
        if segs[0] == "self":
            return list(m), segs[1:]
        base = list(m)
        while segs and segs[0] == "super":
            base, segs = base[:-1], segs[1:]
        return base, segs

    edges = {m: set() for m in files}
    for m, f in files.items():
        text = re.sub(r"#\[cfg\(test\)\]\s*mod tests \{.*", "", f.read_text(), flags=re.S)
        is_mod = f.name in ("mod.rs", "lib.rs")
        for line in text.splitlines():
            s = line.strip()
            if s.startswith("//") or (is_mod and s.startswith("pub use ")):
                continue
            for p in re.findall(r"\b((?:crate|super|self)(?:::[A-Za-z_][A-Za-z0-9_]*)+)(?![A-Za-z0-9_])(?!::\{)", s):
                base, rest = base_of(m, p.split("::"), is_mod)
                t = resolve(base + rest)
                if t is not None and t != m:
                    edges[m].add(t)
            for pre, items in re.findall(r"\b((?:crate|super)(?:::[A-Za-z_][A-Za-z0-9_]*)*)::\{([^}]*)\}", s):
                base, segs = base_of(m, pre.split("::"), is_mod)
                for it in items.split(","):
                    name = it.strip().split(" as ")[0].split("::")
                    if name and name[0]:
                        t = resolve(base + segs + name)
                        if t is not None and t != m:
                            edges[m].add(t)
    return edges


def cycles(edges) -> list[list[tuple[str, ...]]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]
    sys.setrecursionlimit(10_000)

    def strong(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            c = []
            while True:
                w = stack.pop()
                on.discard(w)
                c.append(w)
                if w == v:
                    break
            if len(c) > 1:
                found.append(c)

    for v in edges:
        if v not in index:
            strong(v)
    return found


def test_no_import_cycle_in_src():
    edges = import_graph()
    loops = cycles(edges)
    text = [
        " <-> ".join("::".join(m) for m in sorted(c))
        + "".join(f"\n    {'::'.join(a)} -> {'::'.join(b)}" for a in c for b in edges[a] if b in c)
        for c in loops
    ]
    assert not loops, "import cycles in src/:\n" + "\n".join(text)


def test_the_cycle_finder_finds_a_cycle():
    a, b, c = ("a",), ("b",), ("c",)
    assert cycles({a: {b}, b: {c}, c: {a}}) and not cycles({a: {b}, b: {c}, c: set()})


# ARCHITECTURE.md's table: what each layer may import (itself always)
ALLOWED = {
    "solver": set(),
    "physics": {"solver"},
    "linear": {"physics", "solver"},
    "fmi2": set(),
    "fmi2::fmu": {"fmi2"},
    "fmi2::host": {"fmi2"},
    "slaves": {"physics", "solver", "fmi2", "fmi2::fmu", "models"},
    "cosim": {"fmi2", "fmi2::host", "physics", "solver"},
    "analysis": {"physics"},
    "reference": {"physics", "solver", "linear", "analysis", "slaves", "fmi2", "fmi2::fmu", "fmi2::host", "cosim",
                  "models"},
    "studies": {"analysis", "physics", "linear", "reference", "cosim", "solver", "slaves"},
    "pack": {"fmi2", "fmi2::host"},
    "plot": {"linear"},
    "bench": {"analysis", "physics", "linear", "reference", "cosim", "solver", "fmi2", "fmi2::host", "xorshift"},
    "xorshift": set(),
}


def layer(m: tuple[str, ...]) -> str:
    if not m:
        return "models"  # lib.rs: the generated variable tables
    if m[0] == "fmi2" and len(m) > 1 and m[1] in ("fmu", "host"):
        return f"fmi2::{m[1]}"
    return m[0]


def test_each_layer_imports_only_what_architecture_md_allows():
    wrong = sorted(
        f"{'::'.join(a)} -> {'::'.join(b)}"
        for a, bs in import_graph().items()
        for b in bs
        if layer(a) in ALLOWED and layer(b) != layer(a) and layer(b) not in ALLOWED[layer(a)]
    )
    assert not wrong, "imports ARCHITECTURE.md does not allow:\n" + "\n".join(wrong)


def test_no_command_imports_from_the_dispatcher():
    """src/cli/<command>.rs imports from the library or a sibling, never from cli/mod.rs."""
    wrong = sorted("::".join(a) for a, bs in import_graph().items() if a[:1] == ("cli",) and len(a) == 2 and ("cli",) in bs)
    assert not wrong, f"commands importing from the dispatcher: {wrong}"


def test_no_physics_file_over_700_lines():
    """A physics file does one job (ARCHITECTURE.md): a model's types, its assembly, one stage kind,
    its solver's view; past 700 lines it does several."""
    long = sorted(f"{f.relative_to(ROOT)}: {n}" for f in (SRC / "physics").rglob("*.rs") if (n := len(f.read_text().splitlines())) > 700)
    assert not long, f"physics files over 700 lines: {long}"
