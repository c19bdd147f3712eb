"""The model formats every model command reads: TVL (``.tvl``), UVL (``.uvl``) and DIMACS CNF
(``.dimacs``, ``.cnf``).  One entry point, so that ``--check``, ``count``, ``convert``,
``generate``, pairing and the server's hovers and configurator treat them alike.

    model_format(path) -> "tvl" | "uvl" | "dimacs" | None
    parse_any_model(text, path, read_file=None) -> ModelResult(model, diagnostics)

A DIMACS file is read as a flat model: a root named after the file with every variable as an
optional child and every clause as a constraint (see :mod:`.dimacs`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Callable, Optional

from ..base.diagnostics import Diagnostic, Severity
from ..tvl.model import Model

FORMATS = {".tvl": "tvl", ".uvl": "uvl", ".dimacs": "dimacs", ".cnf": "dimacs"}
# the suffixes a folder walk picks up (".cnf" only when named explicitly: it is a generic name)
MODEL_SUFFIXES = (".tvl", ".uvl", ".dimacs")

ReadFile = Callable[[str], Optional[str]]


@dataclass
class ModelResult:
    model: Model
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity == Severity.ERROR]


def model_format(path: str) -> Optional[str]:
    return FORMATS.get(os.path.splitext(str(path))[1].lower())


def parse_any_model(text: str, path: str, read_file: Optional[ReadFile] = None,
                    fmt: Optional[str] = None) -> ModelResult:
    """Read a model in the format its name says (TVL when it says none); never raises on bad
    input."""
    fmt = fmt or model_format(path) or "tvl"
    if fmt == "uvl":
        from ..uvl import parse_uvl
        r = parse_uvl(text, path, read_file=read_file)
        return ModelResult(r.model, r.diagnostics)
    if fmt == "dimacs":
        from .dimacs import read_dimacs
        model, diags = read_dimacs(text, path)
        return ModelResult(model, diags)
    from ..tvl import parse_model
    r = parse_model(text, path, read_file=read_file)
    return ModelResult(r.model, r.diagnostics)
