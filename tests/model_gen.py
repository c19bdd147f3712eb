"""Generated feature models for tests that need more than a handful of features."""

from __future__ import annotations


def generated_model(n: int, seed: int = 3) -> str:
    """A model of ``n`` features over a few levels of groups, with cross-tree constraints: big
    enough that d4 compiles it in a child process (more than 150 variables)."""
    import random
    rng = random.Random(seed)
    names = [f"F{i}" for i in range(1, n)]
    kids: dict[str, list[str]] = {"Root": []}
    parents = ["Root"]
    for f in names:
        p = rng.choice(parents[-40:])
        kids.setdefault(p, []).append(f)
        kids[f] = []
        parents.append(f)
    kinds = ["allOf", "someOf", "oneOf"]

    def block(f: str, depth: int) -> list[str]:
        ch = kids[f]
        if not ch:
            return []
        kind = "allOf" if f == "Root" else rng.choice(kinds)
        body = []
        for i, c in enumerate(ch):
            opt = "opt " if kind == "allOf" and rng.random() < 0.6 else ""
            inner = block(c, depth + 1)
            sep = "," if i < len(ch) - 1 else ""
            if inner:
                body.append(f"{opt}{c} group {inner[0]}")
                body.extend(inner[1:-1])
                body.append(inner[-1] + sep)
            else:
                body.append(f"{opt}{c}{sep}")
        return [f"{kind} {{"] + ["  " + x for x in body] + ["}"]

    top = block("Root", 0)
    lines = ["root Root group " + top[0]] + top[1:]
    cons = []
    for _ in range(n // 10):
        a, b = rng.sample(names, 2)
        cons.append(f"  {a} -> {b};" if rng.random() < 0.5 else f"  {a} excludes {b};")
    text = "\n".join(lines) + "\n"
    return text + "Root {\n" + "\n".join(cons) + "\n}\n"


def hard_model(n: int = 200, seed: int = 7) -> str:
    """A model whose compilation keeps d4 busy for minutes (``n`` optional features under a
    random 3-CNF at ratio 2.5: easy to satisfy, hard to count): a test that needs d4 to give up
    gets it whatever the machine's speed or load (a model d4 compiles in 0.2 s can still be
    counted under a budget of 0.01 s when its compile thread is next scheduled after d4 ended)."""
    import random
    rng = random.Random(seed)
    names = [f"F{i}" for i in range(1, n + 1)]
    lines = ["root Hard {", "  group allOf {", "    " + ", ".join(f"opt {x}" for x in names), "  }"]
    for _ in range(int(n * 2.5)):
        lits = [("!" if rng.random() < 0.5 else "") + names[v] for v in rng.sample(range(n), 3)]
        lines.append("  " + " || ".join(lits) + ";")
    return "\n".join(lines + ["}"]) + "\n"
