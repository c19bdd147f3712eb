"""Reading a DIMACS CNF: the clauses, the declared variables and the names of ``c <index>
<name>`` comments.  Standard library only: ``tvl-lsp count model.dimacs`` imports this and the
counting service, not the TVL model or its parser (:mod:`.dimacs` turns a CNF into a model)."""

from __future__ import annotations

from typing import Optional

MAX_VARIABLES = 1_000_000  # the biggest industrial model has 14,010; every variable is a feature


class DimacsError(ValueError):
    pass


def parse_dimacs(text: str, errors: Optional[list] = None) -> tuple[int, list[list[int]], dict[int, str], list[int]]:
    """(declared variables, clauses, names by index, line number of each clause).

    Raises :class:`DimacsError` on the first malformed line, unless ``errors`` is a list: then
    each problem is appended to it as ``(line, start column, end column, message)`` and the
    line's bad tokens are skipped."""
    return _parse(text, errors, False)[:4]


def _shift(x: int) -> int:
    return x + 1 if x > 0 else x - 1 if x < 0 else 0


def _parse(text: str, errors: Optional[list], shifted: bool):
    """:func:`parse_dimacs`'s tuple, then the length of every line (``str.splitlines``' lines)
    and the ``(line number, line)`` of the lines that start with ``"c "`` (the names' spans).
    ``shifted``: the clauses over the encoder's variables (DIMACS literal ``x`` is ``x + 1``,
    ``-x`` is ``-x - 1``: the root is variable 1)."""
    all_lines = text.splitlines()
    line_lens = list(map(len, all_lines))
    c_lines: list[tuple[int, str]] = []
    nvars = 0
    names: dict[int, str] = {}
    clauses: list[list[int]] = []
    lines_of: list[int] = []
    cur: list[int] = []
    cur_line = 0
    seen_p = False

    def bad(ln: int, c0: int, c1: int, msg: str) -> None:
        if errors is None:
            raise DimacsError(f"line {ln + 1}: {msg}")
        if len(errors) < 100:
            errors.append((ln, c0, c1, msg))

    lines = enumerate(all_lines)
    for ln, line in lines:
        toks = line.split()
        if not toks:
            continue
        lead = toks[0][0]
        if lead != "c" and lead != "p" and lead != "%":
            # a clause line: all its tokens at once (columns are needed only for a bad token)
            try:
                xs = [x + 1 if x > 0 else x - 1 if x else 0 for x in map(int, toks)] if shifted \
                    else list(map(int, toks))
            except ValueError:
                pass
            else:
                if not cur and xs[-1] == 0 and xs.count(0) == 1:  # one whole clause
                    xs.pop()
                    clauses.append(xs)
                    lines_of.append(ln)
                    continue
                for x in xs:
                    if not cur:
                        cur_line = ln
                    if x == 0:
                        clauses.append(cur)
                        lines_of.append(cur_line)
                        cur = []
                    else:
                        cur.append(x)
                continue
        s = line.strip()
        if s[0] == "c":
            if line.startswith("c "):
                c_lines.append((ln, line))
            parts = s.split(None, 2)
            if len(parts) == 3 and parts[1].isdigit():
                names[int(parts[1])] = parts[2].strip()
            continue
        if s[0] == "p":
            parts = s.split()
            lead = len(line) - len(line.lstrip())
            if len(parts) < 4 or parts[1] != "cnf" or not parts[2].isdigit() or not parts[3].isdigit():
                bad(ln, lead, len(line.rstrip()), f"bad problem line {s!r}: expected 'p cnf VARIABLES CLAUSES'")
                continue
            if seen_p:
                bad(ln, lead, len(line.rstrip()), "a second problem line")
            seen_p = True
            nvars = int(parts[2])
            continue
        if s[0] == "%":
            break
        col = 0
        for tok in s.split():
            col = line.index(tok, col)
            try:
                x = int(tok)
            except ValueError:
                bad(ln, col, col + len(tok), f"{tok!r} is not a literal (a signed variable number, 0 ends a clause)")
                col += len(tok)
                continue
            col += len(tok)
            if not cur:
                cur_line = ln
            if x == 0:
                clauses.append(cur)
                lines_of.append(cur_line)
                cur = []
            else:
                cur.append(_shift(x) if shifted else x)
    for ln, line in lines:  # after a '%' line: its names are not read, their spans are
        if line.startswith("c "):
            c_lines.append((ln, line))
    if cur:
        clauses.append(cur)
        lines_of.append(cur_line)
    return nvars, clauses, names, lines_of, line_lens, c_lines
