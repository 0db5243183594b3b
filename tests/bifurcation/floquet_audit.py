"""An audit of a cycle diagram's special points, independent of the branch code (issue 17).

Along every branch a dense set of orbits is taken: the Hopf ends (multipliers exp(lambda_i T) of straight running,
T = 2 pi / omega), every computed cycle, orbits between consecutive computed cycles and between the Hopf ends and
the nearest cycles (Newton at fixed speed, :func:`bifurcation.cycles.branches.cycle_at`, from a
nearby cycle).  On each orbit the Floquet multipliers are recomputed another way: the monodromy matrix M from the
variational equation Phi' = f_x(x) Phi integrated with the state from x(0) over one period by scipy's DOP853 at
rtol 1e-11, and the non-trivial multipliers as the eigenvalues of the Poincare map's Jacobian on the section
through x(0) normal to f(x(0)), P = (I - f n^T / (n^T f)) M restricted to n^perp (Kuznetsov, Elements of Applied
Bifurcation Theory, 3rd ed. 2004, section 1.5; Seydel, Practical Bifurcation and Stability Analysis, 3rd ed. 2010,
section 7.1).  So no trivial multiplier has to be picked out by its distance from +1.

The test functions are the determinants of Govaerts (Numerical Methods for Bifurcations of Dynamical Equilibria,
SIAM 2000, ch. 7; MatCont's cycle tests): det(P - I) (a real multiplier through +1: a fold of cycles), det(P + I)
(through -1: period doubling) and det(P (.) P - I) = prod_{i<j} (mu_i mu_j - 1) (the bialternate product: a
complex pair through the unit circle, a torus point, or a real pair with mu_i mu_j = 1, a neutral saddle, which is
no bifurcation).  Wherever one changes sign between two consecutive audit orbits, the branch must carry a located
point of that kind there.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from bifurcation.cycles.branches import cycle_at
from bifurcation.cycles.problem import CycleBranch, CycleDiagram, CyclePoint
from bifurcation.special_points import ConvergenceError, PointKind, PointStatus

RTOL = 1e-11
COMPLEX = 1e-6           # |Im mu| above this: a complex multiplier


@dataclass
class AuditOrbit:
    speed: float
    mu: np.ndarray                     # non-trivial multipliers
    cycle: bool                        # False at a Hopf end (the fold test vanishes there: skipped)
    branch_step: float                 # |dV| of the branch segment it lies in (how far a fold may overshoot)


@dataclass
class Audit:
    orbits: int = 0
    failed: int = 0                    # intermediate orbits Newton did not find (reported, not audited)
    changes: dict = field(default_factory=dict)          # kind -> sign changes found
    unmatched: list = field(default_factory=list)        # (kind, speed bracket, branch index)


def poincare_multipliers(family, cycle: CyclePoint) -> np.ndarray:
    """The non-trivial multipliers of ``cycle`` from the variational equation along it (module docstring)."""
    n = family.n
    x0 = cycle.orbit.at(np.array([0.0]))[0]

    def rhs(t, z):
        x, phi = z[:n], z[n:].reshape(n, n)
        return np.concatenate([family.rhs(x, cycle.p, cycle.q),
                               (family.jacobian(x, cycle.p, cycle.q) @ phi).ravel()])

    scale = np.max(np.abs(x0))
    sol = solve_ivp(rhs, (0.0, cycle.period), np.concatenate([x0, np.eye(n).ravel()]), method="DOP853",
                    rtol=RTOL, atol=RTOL * min(scale, 1.0) * 1e-2)
    M = sol.y[n:, -1].reshape(n, n)
    f = family.rhs(x0, cycle.p, cycle.q)
    normal = f / np.linalg.norm(f)
    P = (np.eye(n) - np.outer(f, normal) / (normal @ f)) @ M
    Q = np.linalg.svd(normal[None, :])[2][1:].T                 # orthonormal basis of the section
    return np.linalg.eigvals(Q.T @ P @ Q)


def hopf_end_multipliers(family, hopf) -> np.ndarray:
    """exp(lambda_i T) of straight running with one of the critical pair's two unit multipliers (the trivial
    one) left out."""
    lam = np.linalg.eigvals(family.linear_matrix(hopf.p, hopf.q))
    k = int(np.argmin(np.abs(lam - 1j * hopf.omega)))
    return np.exp(np.delete(lam, k) * 2.0 * np.pi / hopf.omega)


def fold_det(mu):
    return float(np.prod(mu - 1.0).real)


def flip_det(mu):
    return float(np.prod(mu + 1.0).real)


def torus_det(mu):
    i, j = np.triu_indices(len(mu), 1)
    return float(np.prod(mu[i] * mu[j] - 1.0).real)


def is_complex_crossing(mu_a, mu_b) -> bool:
    """Whether the pair whose product is nearest 1 is a complex pair on one side (a torus point, not a neutral
    saddle)."""
    for mu in (mu_a, mu_b):
        i, j = np.triu_indices(len(mu), 1)
        k = int(np.argmin(np.abs(mu[i] * mu[j] - 1.0)))
        if abs(mu[i[k]].imag) > COMPLEX and abs(mu[i[k]] - np.conj(mu[j[k]])) < 1e-6 * max(1.0, abs(mu[i[k]])):
            return True
    return False


TESTS = {PointKind.CYCLE_FOLD: fold_det, PointKind.PERIOD_DOUBLING: flip_det, PointKind.TORUS: torus_det}


def toward(cycle: CyclePoint, hopf, fraction: float) -> tuple[CyclePoint, float]:
    """A predictor a fraction of the way (in amplitude) from ``cycle`` to the Hopf point, and its speed
    (V - V_H proportional to the amplitude squared near a Hopf point)."""
    speed = hopf.p + fraction ** 2 * (cycle.p - hopf.p)
    period = 2.0 * np.pi / hopf.omega + fraction ** 2 * (cycle.period - 2.0 * np.pi / hopf.omega)
    orbit = dataclasses.replace(cycle.orbit, nodes=fraction * cycle.orbit.nodes, period=period)
    return dataclasses.replace(cycle, orbit=orbit, period=period), speed


def audit_orbits(family, branch: CycleBranch, between: int, audit: Audit) -> list[AuditOrbit]:
    """The audit orbits along ``branch`` in branch order, ``between`` of them inside every segment."""
    points = list(branch.points)
    out: list[AuditOrbit] = []
    fractions = [(k + 1) / (between + 1) for k in range(between)]

    def add(cycle, step):
        out.append(AuditOrbit(cycle.p, poincare_multipliers(family, cycle), True, step))
        audit.orbits += 1

    def solve(near, speed):
        try:
            return cycle_at(family, near, speed)
        except ConvergenceError:
            audit.failed += 1
            return None

    def end_segment(cycle, hopf, order):
        cycles = [solve(*toward(cycle, hopf, f)) for f in order]
        for c in cycles:
            if c is not None:
                add(c, abs(cycle.p - hopf.p))

    if branch.start is not None and points:
        out.append(AuditOrbit(branch.start.p, hopf_end_multipliers(family, branch.start), False, 0.0))
        end_segment(points[0], branch.start, fractions)
    for k, p in enumerate(points):
        step = max(abs(p.p - points[max(k - 1, 0)].p), abs(points[min(k + 1, len(points) - 1)].p
                                                                     - p.p))
        add(p, step)
        if k + 1 < len(points):
            q = points[k + 1]
            for f in fractions:
                c = solve(p if f <= 0.5 else q, p.p + f * (q.p - p.p))
                if c is not None:
                    add(c, step)
    if branch.end is not None and points:
        end_segment(points[-1], branch.end, fractions[::-1])
        out.append(AuditOrbit(branch.end.p, hopf_end_multipliers(family, branch.end), False, 0.0))
    return out


def audit_branch(family, branch: CycleBranch, index: int, between: int, audit: Audit) -> None:
    orbits = audit_orbits(family, branch, between, audit)
    located = [p for p in branch.special_points if p.status is PointStatus.LOCATED]
    for a, b in zip(orbits[:-1], orbits[1:]):
        for kind, test in TESTS.items():
            if kind is PointKind.CYCLE_FOLD and not (a.cycle and b.cycle):
                continue
            if not test(a.mu) * test(b.mu) < 0.0:
                continue
            if kind is PointKind.TORUS and not is_complex_crossing(a.mu, b.mu):
                continue                                  # a neutral saddle: no bifurcation to report
            audit.changes[kind] = audit.changes.get(kind, 0) + 1
            lo, hi = sorted((a.speed, b.speed))
            # A fold lies beyond both orbits' speeds, by at most the branch's step there; the others between.
            margin = max(a.branch_step, b.branch_step) if kind is PointKind.CYCLE_FOLD else 1e-9 * hi
            if not any(p.kind is kind and lo - margin <= p.p <= hi + margin for p in located):
                audit.unmatched.append((kind.value, (lo, hi), index))


def audit_diagram(family, diagram: CycleDiagram, between: int = 1) -> Audit:
    audit = Audit()
    for i, b in enumerate(diagram.branches):
        audit_branch(family, b, i, between, audit)
    return audit
