"""The one counting service (issue #15): d4 compiles a model's CNF into a d-DNNF once,
every count is then a pass over it; pyganak counts where d4 cannot (see :mod:`.service`)."""

from .errors import CancelLike, CountCancelled, CountTimeout, EngineFailed
from .service import CNFCounter, CompileStatus, Count, FeatureCounts

__all__ = ["CNFCounter", "CompileStatus", "Count", "FeatureCounts", "CancelLike", "CountCancelled", "CountTimeout",
           "EngineFailed"]
