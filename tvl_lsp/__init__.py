"""tvl-lsp: analysis, CLI and language server for TVL feature models and ROS launch files."""

__version__ = "0.1.0"
