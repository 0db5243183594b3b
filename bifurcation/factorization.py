"""The sparse LU factorization of the discretised systems (collocation and its bordered extensions).

Their matrices are almost block-banded (one block row per collocation interval, the periodicity wrap and a few
dense borders), so their structure is nearly symmetric.  SuperLU's default column order (COLAMD, for
unsymmetric structure) fills them in about six times more than a minimum-degree order on the structure of
A^T + A: on the fold system of a 14-state multibody model (2467 unknowns) 1.30e6 against 2.0e5 entries of L and
U, 38 ms against 7 ms a factorization.  The pivoting, and so the numerical stability, is SuperLU's own either way (Li,
"An overview of SuperLU", ACM TOMS 31, 2005, 302-325; the orderings in its user's guide, section 2.7).
"""

from __future__ import annotations

import scipy.sparse
import scipy.sparse.linalg

ORDER = "MMD_AT_PLUS_A"


def factorize(A) -> scipy.sparse.linalg.SuperLU:
    """The LU factors of the sparse square matrix A (any sparse format), in the minimum-degree order on A^T + A.
    Raises RuntimeError where A is exactly singular, as :func:`scipy.sparse.linalg.splu` does."""
    return scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(A), permc_spec=ORDER)
