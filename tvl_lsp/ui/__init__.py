"""The configurator's browser host (``tvl-lsp ui``) and its built static assets (``static/``,
built from ``editors/configurator`` by ``npm run build``; committed, so that ``pip install``
alone gives a working UI)."""
