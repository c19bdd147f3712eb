"""The configurator (issue #18): pure session logic behind the feature diagram, the
computation graph and the filtered problems -- decisions, propagation, counts, projection,
generation.  No LSP and no HTTP here: :mod:`tvl_lsp.ui` (browser) and the language server's
``tvl-lsp.configurator`` command are its two hosts, both through :func:`api.handle`.
"""

from .session import Refusal, Session, SessionError, configurable_models

__all__ = ["Refusal", "Session", "SessionError", "configurable_models"]
