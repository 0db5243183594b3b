"""The multibody model as a family for the toolkit (:class:`MbsFamily`): its linearisation about straight running
and its right-hand side and derivatives for continuation, through :class:`mbs_shimmy.evaluator.MbsEvaluator`.

Straight running is an equilibrium at every speed, and the speed enters the equations only through the spin
V/R (gyroscopic moments) and the road velocity V of the tyre kinematics, both linearly; so the Jacobian at
straight running is affine in V, A(V) = A0 + V A1, as for the reduced model.  :class:`MbsFamily` forms A0 and A1
from the Jacobians at V = 0 and V = V_REF and checks the affine form against a direct Jacobian at a third speed
(:meth:`MbsFamily.validate`).  The Hopf Newton iteration then sees an exactly affine family and converges to
rounding, where direct difference Jacobians at each speed would leave it ~1e-9 of noise to chase (with the full
geometry it then stalled above its 1e-11 tolerance).  Under braking straight running is the steady state Newton
finds, the same at every speed (:meth:`~reduced_model.family.ShimmyFamily.steady`), and the Jacobian there is affine
in V in the same way.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from mbs_shimmy.forces import layout_of
from mbs_shimmy.layout import Layout
from mbs_shimmy.model import MbsModel
from mbs_shimmy.evaluator import MbsEvaluator, speed_is_time
from bifurcation.derivatives import PARAMETER_STEP, DifferenceDerivatives
from bifurcation.equilibria.normal_form import RealForms
from axles.braking import BRAKE_PARAMS, FREE_ROLLING, Braking
from axles.pressures import PRESSURE_PARAMS, TyrePressures
from reduced_model.family import ShimmyFamily
from axles.parameters import ParameterError

V_REF = 100.0          # m/s: second speed of the affine form
V_LOW = 1.0            # m/s: first speed of the affine form under braking (above the kink at V = 0)
KINKED_FORMS = "differences, not twice differentiable"     # MbsFamily.lyapunov_forms where f has a kink
# what every output says where the full geometry's l1 rests on KINKED_FORMS (docs/results.md)
L1_NOT_WELL_POSED = ("l1 not well posed: the right-hand side is not twice differentiable at straight running (MF 6.1's "
                     "cornering stiffness has |camber|), so l1 by differences is an average across the kink and its "
                     "sign is no criticality: the kink's quadratic coefficient a decides it at vanishing amplitude "
                     "(a > 0 subcritical), the cycle branch at the amplitudes it computes")
V_CHECK = 37.0         # m/s: speed where the affine form is checked against a direct Jacobian
AFFINE_TOL = 1e-8      # relative to max |A|
EQUILIBRIUM_TOL = 1e-9   # |y'| at straight running (rad/s, rad/s^2) above which it is not an equilibrium


class TwinForms(RealForms):
    """The multilinear forms B and C of the MBS at an equilibrium (extended state order) from the twin's exact
    second and third derivatives (:meth:`mbs_shimmy.twin.Twin.second_derivative`, ``third_derivative``),
    extended to complex arguments by multilinearity (:class:`~bifurcation.equilibria.normal_form.RealForms`)."""

    def __init__(self, twin, x0: np.ndarray, speed: float, layout: Layout):
        self.twin, self.x0, self.speed, self.L = twin, np.asarray(x0, dtype=float), float(speed), layout
        self.y0 = self.x0[layout.x_to_y]

    def real_bilinear(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        L = self.L
        return self.twin.second_derivative(self.y0, self.speed, a[L.x_to_y], b[L.x_to_y])[L.y_to_x]

    def real_trilinear(self, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
        L = self.L
        return self.twin.third_derivative(self.y0, self.speed, a[L.x_to_y], b[L.x_to_y], c[L.x_to_y])[L.y_to_x]


@dataclass
class MbsFamily(DifferenceDerivatives, ShimmyFamily):
    """The MBS as a speed family for :func:`bifurcation.equilibria.hopf.find_hopf_points` (with ``lyapunov=False``).

    Same interface as :class:`reduced_model.family.SpeedFamily`: ``n``, ``validate(q)``, ``linear_matrix(V, q)``
    with V in m/s and q the value of ``param`` (``"pressure"``, ``"pressure_right"``, ``"pressure_left"`` in Pa, as
    in :meth:`axles.pressures.TyrePressures.moved`, or a Table 1 entry in SI); matrices are in the extended state order
    :attr:`state_names` (the reduced model's :data:`reduced_model.model.STATE_NAMES`, then ``y_axle``,
    ``y_axle_dot``, ``z_axle``, ``z_axle_dot``, ``phi_gear``, ``phi_gear_dot`` where the full axle has them).
    """

    model: MbsModel = field(default_factory=MbsModel)
    param: str = "pressure"
    pressures: TyrePressures = TyrePressures.uniform(2.5e5)   # operating pressures; "pressure" params move them
    braking: Braking = FREE_ROLLING                           # operating braking; "brake_slip" params move it
    # True: the right-hand sides of continuation are Exudyn's even where the twin covers the system (its Jacobians
    # stay the twin's): the view that polishes an orbit on Exudyn's own residual (:meth:`on_exudyn`)
    exudyn_residuals: bool = False
    _cache: dict = field(default_factory=dict, init=False, repr=False)
    _affine: dict = field(default_factory=dict, init=False, repr=False)
    _equilibria: dict = field(default_factory=dict, init=False, repr=False)
    # the full geometry's forces carry ~1e-10 of rounding (module docstring): a steady state is found to that
    steady_tolerance = EQUILIBRIUM_TOL
    # a wheel's lift-off (and with the camber force, straight running) puts kinks in f: two-parameter cycle curves
    # step over the gaps a collocation node's crossing makes (bifurcation.continuation.step_over)
    piecewise_smooth = True

    def __post_init__(self) -> None:
        self.check_param()

    @property
    def layout(self) -> Layout:
        return layout_of(self.model.fidelity, self.model.dims)

    @property
    def state_names(self) -> tuple[str, ...]:
        return self.layout.state_names

    @property
    def state_units(self) -> tuple[str, ...]:
        return self.layout.state_units

    def _at(self, q: float) -> MbsEvaluator:
        q = float(q)
        found = self._cache.get(q)
        if found is None:
            if len(self._cache) > 64:
                self._cache.clear()
                self._affine.clear()
                self._equilibria.clear()
            pressures, braking = self.operating(q)
            model = self.model
            if self.param not in PRESSURE_PARAMS + BRAKE_PARAMS:
                model = MbsModel(self.model.params.replace(**{self.param: q}), self.model.effects,
                                 self.model.fidelity, self.model.dims)
            found = MbsEvaluator(model.system(pressures, speed_is_time, braking=braking))
            self._cache[q] = found
        return found

    def rhs_mbs(self, y: np.ndarray, speed: float, q: float) -> np.ndarray:
        """y' in MBS order (q, q', alpha1, alpha2), :class:`~mbs_shimmy.system.Layout`."""
        return self._at(q).rhs(np.asarray(y, dtype=float), speed)

    def rhs(self, x: np.ndarray, speed: float, q: float) -> np.ndarray:
        """x' in the extended reduced-model state order (:attr:`state_names`), for real x of shape (n,) (Exudyn's)
        or for each column of x (n, k): the twin's (:meth:`MbsEvaluator.twin_batch`: what continuation evaluates;
        equal to Exudyn's to rounding, and every reported orbit is checked against Exudyn's, :meth:`exudyn_rhs`),
        else Exudyn's."""
        x = np.asarray(x, dtype=float)
        L = self.layout
        if x.ndim == 2 and not self.exudyn_residuals:
            twin = self._at(q).twin_batch(x.T[:, L.x_to_y], speed)
            if twin is not None:
                return twin[0][:, L.y_to_x].T
            return self.exudyn_rhs(x, speed, q)
        return self.rhs_mbs(x[L.x_to_y], speed, q)[L.y_to_x]

    def exudyn_rhs(self, x: np.ndarray, speed: float, q: float) -> np.ndarray:
        """x' by Exudyn for each column of x (n, k) (or for x of shape (n,)): one call each."""
        x = np.asarray(x, dtype=float)
        if x.ndim == 2:
            return np.stack([self.exudyn_rhs(column, speed, q) for column in x.T], axis=1)
        L = self.layout
        return self.rhs_mbs(x[L.x_to_y], speed, q)[L.y_to_x]

    def jacobian(self, x: np.ndarray, speed: float, q: float) -> np.ndarray:
        """df/dx (extended order): the twin's, or Exudyn's five-point differences where the twin has none."""
        L = self.layout
        ev = self._at(q)
        y = np.asarray(x, dtype=float)[L.x_to_y]
        exact = ev.exact_jacobian(y, speed)
        J = exact[0] if exact is not None else ev.jacobian(y, speed)
        return J[np.ix_(L.y_to_x, L.y_to_x)]

    def rhs_and_jacobians(self, P: np.ndarray, speed: float, q: float,
                          kink_rows: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """f and df/dx at the states P (M, n) (extended order): what collocation needs.  Both from the twin in one
        call (:meth:`MbsEvaluator.twin_batch`; ``kink_rows`` False: no differences near a lift-off, the twin's
        exact one-sided df/dx, :meth:`bifurcation.problem.Family.rhs_and_jacobians`), or with
        :attr:`exudyn_residuals` per state Exudyn's f with the twin's df/dx (:meth:`MbsEvaluator.exact_jacobian`)
        or :meth:`MbsEvaluator.rhs_and_jacobian`'s differences."""
        ev = self._at(q)
        L = self.layout
        P = np.asarray(P, dtype=float)
        twin = None if self.exudyn_residuals else ev.twin_batch(P[:, L.x_to_y], speed, jacobians=True,
                                                                  kink_rows=kink_rows)
        if twin is not None:
            return twin[0][:, L.y_to_x], twin[1][np.ix_(np.arange(len(P)), L.y_to_x, L.y_to_x)]
        f, J = np.empty(P.shape), np.empty(P.shape + (P.shape[1],))
        for k, x in enumerate(P):
            y = x[L.x_to_y]
            exact = ev.exact_jacobian(y, speed, key=k)
            if exact is None:
                fy, Jy = ev.rhs_and_jacobian(y, speed)
            else:
                fy, Jy = ev.rhs(y, speed), exact[0]
            f[k], J[k] = fy[L.y_to_x], Jy[np.ix_(L.y_to_x, L.y_to_x)]
        return f, J

    def parameter_derivative(self, P: np.ndarray, p: float, q: float, free: str, scale: float) -> np.ndarray:
        """df/d(free) at the states P (M, n): in the speed from the twin (:meth:`MbsEvaluator.twin_batch`), else
        by central differences of Exudyn's right-hand side; in the second parameter by central differences of
        :meth:`rhs` (the twin with the numbers of q +- h: one graph, two Exudyn systems to read them from)."""
        if free == self.primary:
            L = self.layout
            twin = self._at(q).twin_batch(np.asarray(P, dtype=float)[:, L.x_to_y], p, jacobians=True,
                                          kink_rows=False)
            if twin is not None:
                return twin[2][:, L.y_to_x]
            return super().parameter_derivative(P, p, q, free, scale)
        # the second parameter: the model rebuilt at q +- h, its twin one graph with other numbers
        h = PARAMETER_STEP * max(abs(q), scale)
        P = np.asarray(P, dtype=float)
        return (self.rhs(P.T, p, q + h) - self.rhs(P.T, p, q - h)).T / (2.0 * h)

    def on_exudyn(self) -> "MbsFamily":
        """The same family (sharing its assembled systems and twins) with Exudyn's right-hand sides in every
        continuation step and the twin's Jacobians: Newton on it polishes an orbit on Exudyn's own residual."""
        view = dataclasses.replace(self, exudyn_residuals=True)
        view._cache, view._affine = self._cache, self._affine
        return view

    def multilinear_forms(self, x0: np.ndarray, p: float, q: float):
        """B and C at the equilibrium x0 (speed p): exact from the twin (:class:`TwinForms`) where it covers the
        system, x0's loads lie in the load table and f is twice differentiable at x0; else by differences of
        Exudyn's right-hand side (the full geometry's camber force is not: MF 6.1's cornering stiffness has
        |camber|, which is zero at straight running; exact derivatives there take one side of the kink, differences
        average over their step, and neither is the l1 of a smooth normal form, docs/results.md)."""
        ev = self._at(q)
        L = self.layout
        smooth = self.twice_differentiable(x0, p, q)
        if smooth:
            ev.twin_forms += 1
            return TwinForms(ev.twin, x0, p, L)
        if smooth is None:
            ev.difference_forms += 1
        else:
            ev.kinked_forms += 1
        return super().multilinear_forms(x0, p, q)

    def twice_differentiable(self, x0: np.ndarray, speed: float, q: float) -> bool | None:
        """Whether f is twice differentiable at x0 (extended order), None where the twin cannot tell (no twin, or a
        load outside its table).  Across x0 along a fixed direction of every state, the jump of the twin's D^2 f
        shrinks tenfold with a tenfold smaller offset where f is smooth (measured: 0.1000 without the camber force)
        and stays where it has a kink (0.96 with it)."""
        twin = self._at(q).twin
        L = self.layout
        y0 = np.asarray(x0, dtype=float)[L.x_to_y]
        if twin is None or twin.jacobian_and_near_kink(y0, speed)[2:] != (True, False):
            return None
        z = (np.cos(1.7 * np.arange(self.n) + 0.3) * self.state_scales(1.0))[L.x_to_y]
        jumps = [float(np.max(np.abs(twin.second_derivative(y0 + e * z, speed, z, z)
                                     - twin.second_derivative(y0 - e * z, speed, z, z)))) for e in (1e-5, 1e-6)]
        size = float(np.max(np.abs(twin.second_derivative(y0, speed, z, z))))
        return jumps[1] <= 1e-9 * max(size, 1.0) or jumps[1] < 0.5 * jumps[0]

    @property
    def lyapunov_forms(self) -> str:
        """Which multilinear forms the normal-form coefficients so far used: ``"twin"`` (exact), ``"differences"``
        (of Exudyn's right-hand side; :data:`KINKED_FORMS` where f has a kink at the
        equilibrium, :meth:`multilinear_forms`), several of them joined by ``" and "``, or ``"none"``."""
        used = [("twin", sum(ev.twin_forms for ev in self._cache.values())),
                ("differences", sum(ev.difference_forms for ev in self._cache.values())),
                (KINKED_FORMS, sum(ev.kinked_forms for ev in self._cache.values()))]
        return " and ".join(name for name, count in used if count) or "none"

    @property
    def derivatives(self) -> str:
        """Which derivatives the results so far used: ``"twin"`` (exact, :mod:`mbs_shimmy.twin`),
        ``"differences"`` (of Exudyn's right-hand side) or ``"twin and differences"``."""
        twin = sum(ev.twin_jacobians for ev in self._cache.values())
        diff = sum(ev.difference_jacobians for ev in self._cache.values())
        return {(True, False): "twin", (False, True): "differences", (True, True): "twin and differences"}.get(
            (twin > 0, diff > 0), "none")

    @property
    def rhs_calls(self) -> int:
        """Right-hand-side evaluations by Exudyn so far, over every second-parameter value evaluated."""
        return sum(ev.calls for ev in self._cache.values())

    @property
    def twin_calls(self) -> int:
        """Right-hand sides (with or without Jacobians) evaluated by the twin so far."""
        return sum(ev.twin_calls for ev in self._cache.values())

    def mass_matrix(self, q: float) -> np.ndarray:
        """The mass matrix of the mechanical coordinates at straight running (tree order)."""
        return self._at(q).mass_matrix(np.zeros(self.n))

    def direct_linear_matrix(self, speed: float, q: float) -> np.ndarray:
        """Jacobian at straight running by Exudyn's five-point differences at this speed (reduced-model state order):
        at x = 0, or under braking at the steady state (which does not depend on the speed,
        :meth:`ShimmyFamily.steady`).  Not the twin's: at straight running the differences are good to 1e-11
        (module docstring) for 56 calls, about 5 ms (the choice dates from a twin graph per parameter value; now
        one graph serves them all, :mod:`mbs_shimmy.twin`)."""
        L = self.layout
        x0 = self.equilibrium(speed, q) if self.braked else np.zeros(self.n)
        return self._at(q).jacobian(x0[L.x_to_y], speed)[np.ix_(L.y_to_x, L.y_to_x)]

    def affine_matrices(self, q: float) -> tuple[np.ndarray, np.ndarray]:
        """(A0, A1) with A(V) = A0 + V A1 at straight running (module docstring)."""
        q = float(q)
        found = self._affine.get(q)
        if found is None:
            if self.braked:
                # off x = 0 the full geometry's slip rate |v_x| alpha has a kink at V = 0 (v_x of a steered wheel's
                # leading point changes sign with the yaw rate): the affine form from two speeds above it
                low = self.direct_linear_matrix(V_LOW, q)
                A1 = (self.direct_linear_matrix(V_REF, q) - low) / (V_REF - V_LOW)
                A0 = low - V_LOW * A1
            else:
                A0 = self.direct_linear_matrix(0.0, q)
                A1 = (self.direct_linear_matrix(V_REF, q) - A0) / V_REF
            found = self._affine[q] = (A0, A1)
        return found

    def linear_matrix(self, speed: float, q: float) -> np.ndarray:
        """Jacobian at straight running (reduced-model state order): A0 + V A1, see :meth:`validate`."""
        A0, A1 = self.affine_matrices(q)
        return A0 + speed * A1

    def affine_residual(self, speed: float, q: float) -> float:
        """max |A_direct(V) - (A0 + V A1)| / max |A_direct(V)|."""
        direct = self.direct_linear_matrix(speed, q)
        return float(np.max(np.abs(direct - self.linear_matrix(speed, q))) / np.max(np.abs(direct)))

    def equilibrium(self, speed: float, q: float) -> np.ndarray:
        """Straight running: x = 0 free rolling (checked), the steady state by Newton under braking."""
        if self.braked:
            return self.steady(speed, q)
        x0 = np.zeros(self.n)
        residual = float(np.max(np.abs(self.rhs(x0, speed, q))))
        if residual > EQUILIBRIUM_TOL:
            raise ParameterError(f"straight running is not an equilibrium of the MBS here (|f(0)| = {residual:.3g})")
        return x0

    def validate(self, q: float) -> None:
        """Raise :class:`ParameterError` where the model is meaningless or straight running is no equilibrium;
        raise RuntimeError if the Jacobian is not affine in the speed (it must be: module docstring)."""
        self._at(q)
        self.equilibrium(1.0, q)
        residual = self.affine_residual(V_CHECK, q)
        if residual > AFFINE_TOL:
            raise RuntimeError(f"the MBS Jacobian at straight running is not affine in the speed "
                               f"(residual {residual:.2e}): the affine Hopf seeding does not apply")
