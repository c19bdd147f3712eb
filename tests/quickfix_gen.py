"""Random small feature models with anomalies, written as TVL or UVL (quick-fix tests)."""

from __future__ import annotations

import random
from collections import Counter
import re


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


# ------------------------------------------------------------------ planted anomalies

PREFIXES = ("F", "Sensor", "Arm_", "Nav", "Cam", "Drive")


def planted_model(seed: int, fmt: str) -> tuple[str, set, list]:
    """A random feature tree with no anomaly, a few harmless constraints, and anomalies planted
    by constraints of known effect: each of a dead feature, a false-optional feature and a
    redundant constraint in a couple of forms, on distinct features (on the same ones, their
    effects mixed, for every fifth seed: nothing is said planted then); a void model in one of
    three forms for every fourth seed.  Returns the text, the finding keys planted (``{("void-model",)}`` only for a
    void model: its check reports nothing else), the constraints planted to make it void (their
    text) and ``without(texts)``: the text without the constraints written ``texts``, one per
    mention (what a
    void model's check hides is the findings of the model without its conflict)."""
    rng = random.Random(seed * 7919 + (fmt == "uvl"))
    n = rng.randint(9, 20)
    names = [f"{rng.choice(PREFIXES)}{i}" for i in range(1, n)]
    kids: dict[str, list[str]] = {"Root": []}
    parent: dict[str, str] = {}
    order = ["Root"]
    for f in names:
        p = rng.choice(order[-5:])
        kids[p].append(f)
        kids[f] = []
        parent[f] = p
        order.append(f)
    kinds: dict[str, str] = {}
    opt: dict[str, bool] = {}
    for f in order:
        ch = kids[f]
        if not ch:
            continue
        kinds[f] = "allOf" if f == "Root" or len(ch) < 2 else rng.choice(["allOf", "allOf", "oneOf", "someOf"])
        for c in ch:
            opt[c] = kinds[f] == "allOf" and rng.random() < 0.55
    core = {"Root"}
    for f in order[1:]:
        if parent[f] in core and kinds[parent[f]] == "allOf" and not opt[f]:
            core.add(f)
    free = [f for f in order[1:] if opt[f] and parent[f] in core]   # optional children of core features

    def below(f: str) -> set:
        out, todo = set(), [f]
        while todo:
            x = todo.pop()
            out.add(x)
            todo.extend(kids[x])
        return out

    used: set = set()
    cons: list[tuple] = []    # (a, nega, op, b, negb)
    planted: set = set()
    void_cons: list = []

    overlap = seed % 5 == 4   # anomalies planted on the same features: their effects mix

    def pick(pool):
        pool = [f for f in pool if overlap or f not in used]
        return rng.choice(pool) if pool else None
    corel = sorted(core, key=order.index)
    plans = ["dead", "false-optional", "redundant"] + rng.sample(["dead", "false-optional", "redundant"],
                                                                   rng.randint(0, 2))
    rng.shuffle(plans)
    for plan in plans:
        if plan == "dead":
            d = pick(free)
            if d is None:
                continue
            used.update(below(d))
            k = rng.choice(corel)
            cons.append(rng.choice([(k, "", "->", d, "!"), (d, "", "->", k, "!"), (d, "", "->", parent[d], "!")]))
            planted.add(("dead-feature", d))
        elif plan == "false-optional":
            o = pick(free)
            if o is None:
                continue
            used.update(below(o))
            p = parent[o]
            k = rng.choice(corel)
            cons.append(rng.choice([(p, "", "->", o, ""), (k, "", "->", o, ""), (o, "!", "->", p, "!")]))
            planted.add(("false-optional", o, p))
        else:
            c = pick(order[1:])
            if c is None:
                continue
            mand = [m for m in kids[c] if kinds[c] == "allOf" and not opt[m]]
            forms = [(c, "", "->", parent[c], ""), (c, "", "->", "Root", "")]
            if mand:
                forms.append((c, "", "->", rng.choice(mand), ""))
            form = rng.choice(forms)
            if form[0] == form[3]:
                continue
            used.add(c)
            cons.append(form)
            planted.add(("redundant-constraint", _con(fmt, *form)))
    # harmless constraints between optional children of core features (neither dead nor
    # forced: both may be left out)
    spare = [f for f in free if f not in used]
    for _ in range(rng.randint(0, 2)):
        if len(spare) < 2:
            break
        a, b = rng.sample(spare, 2)
        cons.append((a, "", "->", b, ""))
        spare.remove(a)
    if seed % 4 == 3 and len(corel) >= 2:
        k, m = rng.sample(corel, 2)
        x = pick(free)
        form = rng.randrange(3) if x is not None else 0
        if form == 0:
            vc = [(k, "", "->", m, "!")]
        elif form == 1:
            vc = [(k, "", "->", x, ""), (x, "", "->", m, "!")]
        else:
            vc = [(k, "", "->", x, ""), (k, "", "->", x, "!")]
        for c in vc:
            cons.insert(rng.randrange(len(cons) + 1), c)
        void_cons = [_con(fmt, *c) for c in vc]
        planted = {("void-model",)}
    # where each constraint is written: the root's block or the constraints section, else the
    # block (TVL) or the attributes (UVL) of its first feature
    where = [c[0] != "Root" and rng.random() < 0.3 for c in cons]
    layout = rng.random()
    text = _render(fmt, kids, kinds, opt, cons, where, layout)
    def without(gone) -> str:
        left = Counter(gone)   # (a constraint written twice: one goes per mention)
        keep = []
        for i, c in enumerate(cons):
            if left[_con(fmt, *c)] > 0:
                left[_con(fmt, *c)] -= 1
            else:
                keep.append(i)
        return _render(fmt, kids, kinds, opt, [cons[i] for i in keep], [where[i] for i in keep], layout)
    return text, (set() if overlap and not void_cons else planted), void_cons, without


def _render(fmt, kids, kinds, opt, cons, where, layout: float) -> str:
    attached: dict[str, list[str]] = {}
    rendered = []
    for c, w in zip(cons, where):
        if w:
            attached.setdefault(c[0], []).append(_con(fmt, *c))
        else:
            rendered.append(_con(fmt, *c))
    if fmt == "tvl":
        text = _tvl(kids, kinds, opt, [])
        body = "".join(f"  {c}\n" for c in rendered)
        text = text[:text.rindex("}")] + body + "}\n"
        for f, cs in attached.items():
            text += f"\n{f} {{\n" + "".join(f"  {c}\n" for c in cs) + "}\n"
        return text
    text = _uvl(kids, kinds, opt, [], random.Random(layout))
    ind = "\t" if "\n\tRoot" in text else "    "
    for f, cs in attached.items():
        attrs = f"{{constraint {cs[0]}}}" if len(cs) == 1 else f"{{abstract, constraints [{', '.join(cs)}]}}"
        text = re.sub(rf"^(\s+{f})$", lambda m: f"{m.group(1)} {attrs}", text, count=1, flags=re.M)
    return text.replace("constraints\n", "") + ("constraints\n" + "".join(f"{ind}{c}\n" for c in rendered)
                                                 if rendered else "")


def _con(fmt: str, a: str, na: str, op: str, b: str, nb: str) -> str:
    if fmt == "tvl":
        return f"{na}{a} {op} {nb}{b};"
    return f"{na}{a} {'=>' if op == '->' else op} {nb}{b}"
