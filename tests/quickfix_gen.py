"""Random small feature models with anomalies, written as TVL or UVL (quick-fix tests)."""

from __future__ import annotations

import random


def random_model(seed: int, fmt: str, n: int = 10, constraints: int = 5) -> str:
    rng = random.Random(seed)
    names = [f"F{i}" for i in range(1, n)]
    kids: dict[str, list[str]] = {"Root": []}
    order = ["Root"]
    for f in names:
        p = rng.choice(order[-6:])
        kids[p].append(f)
        kids[f] = []
        order.append(f)
    kinds: dict[str, str] = {}
    opt: dict[str, bool] = {}
    for f, ch in kids.items():
        if ch:
            kinds[f] = rng.choice(["allOf", "allOf", "oneOf", "someOf"])
            for c in ch:
                opt[c] = kinds[f] == "allOf" and rng.random() < 0.6
    ops = ["->", "->", "excludes", "&&", "||", "<->"]
    cons = []
    for _ in range(constraints):
        a, b = rng.sample(order, 2)
        op = rng.choice(ops)
        na = "!" if rng.random() < 0.2 else ""
        nb = "!" if rng.random() < 0.3 else ""
        cons.append((na, a, op, nb, b))
    if fmt == "tvl":
        return _tvl(kids, kinds, opt, cons)
    return _uvl(kids, kinds, opt, cons, rng)


def _tvl(kids, kinds, opt, cons) -> str:
    def block(f: str, ind: str) -> list[str]:
        ch = kids[f]
        out = [f"{ind}group {kinds[f]} {{"]
        for i, c in enumerate(ch):
            sep = "," if i < len(ch) - 1 else ""
            head = f"{ind}  {'opt ' if opt.get(c) else ''}{c}"
            if kids[c]:
                inner = block(c, ind + "  ")
                out.append(head + " " + inner[0].strip())
                out.extend(inner[1:-1])
                out.append(inner[-1] + sep)
            else:
                out.append(head + sep)
        out.append(f"{ind}}}")
        return out
    lines = ["root Root {"]
    if kids["Root"]:
        lines += block("Root", "  ")
    for na, a, op, nb, b in cons:
        if op == "excludes":
            lines.append(f"  {a} excludes {b};")
        else:
            lines.append(f"  {na}{a} {op} {nb}{b};")
    lines.append("}")
    return "\n".join(lines) + "\n"


def _uvl(kids, kinds, opt, cons, rng) -> str:
    kw = {"oneOf": "alternative", "someOf": "or"}
    ind = "    " if rng.random() < 0.5 else "\t"
    lines = ["features"]

    def tree(f: str, depth: int) -> None:
        lines.append(ind * depth + f)
        ch = kids[f]
        if not ch:
            return
        if kinds[f] == "allOf":
            groups = [("mandatory", [c for c in ch if not opt[c]]), ("optional", [c for c in ch if opt[c]])]
            if rng.random() < 0.5:
                groups.reverse()
        else:
            groups = [(kw[kinds[f]], ch)]
        for g, members in groups:
            if not members:
                continue
            lines.append(ind * (depth + 1) + g)
            for c in members:
                tree(c, depth + 2)
    tree("Root", 1)
    lines.append("constraints")
    sym = {"->": "=>", "&&": "&", "||": "|", "<->": "<=>"}
    for na, a, op, nb, b in cons:
        if op == "excludes":
            lines.append(f"{ind}{a} => !{b}")
        else:
            lines.append(f"{ind}{na}{a} {sym[op]} {nb}{b}")
    return "\n".join(lines) + "\n"
