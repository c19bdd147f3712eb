"""The server's settings: ``initializationOptions`` or the ``workspace/configuration`` section
``tvl-lsp``::

    {"diagnostics": {"<code>": "off" | "error" | "warning" | "information" | "hint"},
     "count": {"timeBudget": 10},          # seconds per count (CPU) / solver-backed check
     "generate": {"folder": "configs",     # relative to the launch file's package, or absolute
                  "limit": 100},           # files per "generate" action
     "debounce": 0.15}                     # seconds of quiet before the solver-backed pass

Plain data, no pygls: :meth:`Settings.update` takes what the client sent (nested or flat
dotted keys) and ignores what it does not understand.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Optional

from ..base.diagnostics import Diagnostic, Severity

SEVERITIES = {"error": Severity.ERROR, "warning": Severity.WARNING,
              "information": Severity.INFORMATION, "info": Severity.INFORMATION, "hint": Severity.HINT}



@dataclass
class Settings:
    diagnostics: dict[str, str] = field(default_factory=dict)  # code -> off|error|warning|information|hint
    time_budget: float = 10.0      # seconds for a count / solver-backed check
    generate_folder: Optional[str] = None
    generate_limit: int = 100
    debounce: float = 0.15         # seconds of quiet before the solver-backed pass

    def update(self, data: Any) -> None:
        if not isinstance(data, dict):
            return
        if "tvl-lsp" in data and isinstance(data["tvl-lsp"], dict):
            data = data["tvl-lsp"]
        # flat keys as some clients send them: "count.timeBudget", "tvl-lsp.generate.folder"
        nested: dict = {}
        for k, v in data.items():
            parts = str(k).split(".")
            if parts[0] == "tvl-lsp":
                parts = parts[1:]
            if len(parts) > 1:
                cur = nested
                for p in parts[:-1]:
                    cur = cur.setdefault(p, {})
                cur[parts[-1]] = v
        if nested:
            data = {**{k: v for k, v in data.items() if "." not in str(k)}, **nested}
        diags = data.get("diagnostics")
        if isinstance(diags, dict):
            self.diagnostics = {str(k): str(v).lower() for k, v in diags.items()
                                if str(v).lower() in SEVERITIES or str(v).lower() == "off"}
        count = data.get("count")
        if isinstance(count, dict) and isinstance(count.get("timeBudget"), (int, float)):
            self.time_budget = max(0.1, float(count["timeBudget"]))
        gen = data.get("generate")
        if isinstance(gen, dict):
            if isinstance(gen.get("folder"), str):
                self.generate_folder = gen["folder"] or None
            if isinstance(gen.get("limit"), int) and gen["limit"] > 0:
                self.generate_limit = gen["limit"]
        if isinstance(data.get("debounce"), (int, float)):
            self.debounce = max(0.0, float(data["debounce"]))

    def severity(self, d: Diagnostic) -> Optional[Severity]:
        """The severity to report ``d`` with, or None when its code is turned off."""
        s = self.diagnostics.get(d.code)
        if s is None:
            return d.severity
        if s == "off":
            return None
        return SEVERITIES[s]

