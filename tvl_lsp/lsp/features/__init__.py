"""LSP features, one module each, registered in one place (:func:`register_all`)."""

from __future__ import annotations

FEATURE_MODULES = (
    "sync",          # documents, settings, workspace folders, watched files
    "diagnostics",   # pull diagnostics (push is the server's scheduler)
    "hover",
    "navigation",    # definition, declaration, references, rename
    "completion",
    "structure",     # document symbols, folding ranges, semantic tokens
    "formatting",
    "code_actions",
    "code_lens",
    "commands",      # configurator + configuration generation
    "graph",         # the computation graph command (hover uses it too)
    "configurator",  # the configurator view's one request (tvl-lsp.configurator)
    "explain",       # a diagnostic code's page (tvl-lsp.explain; the hover uses it too)
)


def register_all(server) -> None:
    import importlib
    for name in FEATURE_MODULES:
        importlib.import_module(f"{__name__}.{name}").register(server)
