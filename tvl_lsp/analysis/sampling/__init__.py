"""T-wise sampling at industrial scale (t = 1, 2, 3): a small set of products of a CNF that
together contain every valid combination of ``t`` feature literals.

    from tvl_lsp.analysis.sampling import sample
    r = sample(clauses, n, t=2, seed=0, assumptions=(), budget=120.0, jobs=1)
    r.products      # lists of the literals of features 1..n, each a model of the CNF
    r.complete      # every valid interaction covered (False: the budget ran out first)
    r.covered, r.left, r.invalid, r.coverage

How (YASA / IncLing / AETG, read not copied; see ``docs/sampling.md``):

1. :mod:`.prepare`: one SAT solver on the CNF, kept warm for the whole run; the backbone (core
   and dead features: not part of any interaction), the literals each literal forces by unit
   propagation, and classes of equivalent features (one representative each);
2. :mod:`.pairwise` (t = 1, 2) and :mod:`.triples` (t = 3): configurations grown one at a time,
   each variable towards the literal with more uncovered interactions with what the configuration
   already has; unit propagation rules out most conflicts, one SAT call per configuration checks
   it (more only when propagation missed one: the core says which decision to drop), and an
   interaction that proves invalid is learnt once;
3. every configuration is a solver model, and the run stops only when every interaction is
   covered or proven invalid -- or when the budget or the caller stops it: then the result says
   so, with the coverage reached and the interactions left.

Deterministic for a seed (and independent of ``jobs``) whenever the budget does not stop it.
"""

from .sampler import MAX_TRIPLE_MEMORY, SampleResult, sample

__all__ = ["MAX_TRIPLE_MEMORY", "SampleResult", "sample"]
