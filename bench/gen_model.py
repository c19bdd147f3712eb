"""A random TVL model of N features (deterministic for a seed), for benchmarks."""

from __future__ import annotations

import random


def generate_model(n: int = 2000, seed: int = 1, constraints: int = 60) -> str:
    rng = random.Random(seed)
    names = [f"F{i}" for i in range(n)]
    names[0] = "Root"
    children: dict[int, list[int]] = {i: [] for i in range(n)}
    for i in range(1, n):
        parent = rng.randrange(max(1, i - 40), i) if i > 1 else 0
        children[parent].append(i)
    lines: list[str] = []

    def emit(i: int, depth: int, opt: bool) -> None:
        ind = "  " * depth
        head = ("root " if i == 0 else ("opt " if opt else "")) + names[i]
        kids = children[i]
        if not kids:
            lines.append(ind + head)
            return
        kind = rng.choice(["allOf", "allOf", "someOf", "oneOf"])
        lines.append(f"{ind}{head} group {kind} {{")
        for j, k in enumerate(kids):
            emit(k, depth + 1, kind == "allOf" and rng.random() < 0.6)
            if j < len(kids) - 1:
                lines[-1] += ","
        lines.append(ind + "}")

    emit(0, 0, False)
    body = "\n".join(lines)
    cons = []
    for _ in range(constraints):
        a, b = rng.sample(range(1, n), 2)
        cons.append(f"  {names[a]} -> {names[b]};" if rng.random() < 0.7 else f"  !({names[a]} && {names[b]});")
    # constraints go in a reopening of the root
    return body + "\n\nRoot {\n" + "\n".join(cons) + "\n}\n"


if __name__ == "__main__":
    import sys
    print(generate_model(int(sys.argv[1]) if len(sys.argv) > 1 else 2000))
