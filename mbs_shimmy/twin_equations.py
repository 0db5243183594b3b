"""The multibody equations of an assembled Exudyn system, read from Exudyn's own items, as generic scalar code.

The differentiable twin (:mod:`mbs_shimmy.twin`) traces these functions with JAX (or CasADi) values; nothing here
is typed twice from the model's definitions:

* the kinematic trees are Exudyn's stored ``ObjectKinematicTree`` items (joint types, parents, joint
  transformations and offsets, link masses, centres of mass and inertias, the joints' P/D control): forward
  kinematics as Exudyn defines it, link frame = parent frame x joint transformation x joint motion (Exudyn
  theory manual, ObjectKinematicTree), and the kinetic energy of the links;
* the markers (``MarkerKinematicTreeRigid`` at link points, ``MarkerBodyPosition`` on the ground) and the
  ``ObjectConnectorSpringDamper`` linkage (f = k (L - L0) + d (L' - v0) + f0 along the connector);
* the force user function's generalized forces are :func:`mbs_shimmy.compiled_stage.stage_terms`, the function the
  compiled solver stage of the user function itself runs, with its constants array.

Mass matrix and velocity terms then follow by automatic differentiation of the kinetic energy (Lagrange's
equations), in the backend.  Vectors are 3-tuples and matrices tuples of rows, so that the same text runs on any
scalar type that has the arithmetic operators.
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass

import numpy as np

from mbs_shimmy import compiled_stage

REVOLUTE = {"RevoluteX": 0, "RevoluteY": 1, "RevoluteZ": 2}
PRISMATIC = {"PrismaticX": 0, "PrismaticY": 1, "PrismaticZ": 2}


class NotCovered(ValueError):
    """The system has an item the twin does not reproduce (its derivatives stay differences)."""


@dataclass(frozen=True)
class Tree:
    """One ``ObjectKinematicTree`` as Exudyn stores it (plain floats)."""

    kinds: tuple[tuple[str, int], ...]      # ("R" | "P", axis) per link
    parents: tuple[int, ...]
    rotations: tuple                        # joint transformation (rows) per link
    offsets: tuple                          # joint offset per link
    masses: tuple[float, ...]
    coms: tuple
    inertias: tuple                         # about the centre of mass, in the link frame
    p_control: tuple[float, ...]
    d_control: tuple[float, ...]
    q_offsets: tuple[float, ...]
    v_offsets: tuple[float, ...]

    @classmethod
    def of(cls, item: dict) -> "Tree":
        if np.any(np.asarray(item["gravity"]) != 0.0) or np.any(np.asarray(item["baseOffset"]) != 0.0):
            raise NotCovered("a kinematic tree with gravity or a base offset")
        if len(item["linkForces"]) or len(item["linkTorques"]) or len(item["jointForceVector"]):
            raise NotCovered("a kinematic tree with link forces")
        def items(key):
            # by index: Exudyn's fast build has no range checks, so iterating its lists runs past their end
            seq = item[key]
            return [seq[i] for i in range(len(seq))]

        kinds = []
        for jt in items("jointTypes"):
            name = jt.name
            if name in REVOLUTE:
                kinds.append(("R", REVOLUTE[name]))
            elif name in PRISMATIC:
                kinds.append(("P", PRISMATIC[name]))
            else:
                raise NotCovered(f"joint type {name}")

        def rows(m):
            return tuple(tuple(float(v) for v in r) for r in np.asarray(m))

        def vec(v):
            return tuple(float(x) for x in np.asarray(v))
        return cls(tuple(kinds), tuple(int(p) for p in items("linkParents")),
                   tuple(rows(np.asarray(h)[:3, :3]) for h in items("jointHTs")),
                   tuple(vec(np.asarray(h)[:3, 3]) for h in items("jointHTs")),
                   tuple(float(m) for m in items("linkMasses")), tuple(vec(c) for c in items("linkCOMs")),
                   tuple(rows(i) for i in items("linkInertiasCOM")), vec(items("jointPControlVector")),
                   vec(items("jointDControlVector")), vec(items("jointPositionOffsetVector")),
                   vec(items("jointVelocityOffsetVector")))


@dataclass(frozen=True)
class Point:
    """A marker's point: on a tree's link (``tree`` index into :attr:`TwinData.trees`) or fixed (tree -1)."""

    tree: int
    link: int
    local: tuple


@dataclass(frozen=True)
class Spring:
    """An ``ObjectConnectorSpringDamper`` between two marker points."""

    ends: tuple[Point, Point]
    length: float
    stiffness: float
    damping: float
    force: float
    velocity_offset: float


@dataclass(frozen=True)
class TwinData:
    """Everything the twin's equations read from one assembled :class:`~mbs_shimmy.system.MbsSystem`."""

    trees: tuple[Tree, ...]          # the first carries the inertia
    knuckles: tuple[Point, Point]
    springs: tuple[Spring, ...]
    m: int                           # mechanical coordinates; the tree has m + 2
    constants: np.ndarray            # the compiled stage's constants and load tables
    tables: np.ndarray

    @classmethod
    def of(cls, system) -> "TwinData":
        """Read the system's items; :class:`NotCovered` where the twin has no counterpart."""
        forces = system.forces
        if forces.stage is None:
            raise NotCovered("the Python user function runs (the first-order kinematics of small_angles)")
        if not forces.steady:
            raise NotCovered("a speed schedule with acceleration")
        mbs = system.mbs
        order = [int(system.tree)] + ([int(system.geometry_tree)] if system.geometry_tree != system.tree else [])
        trees = tuple(Tree.of(mbs.GetObject(t)) for t in order)

        def point(marker: int) -> Point:
            mk = mbs.GetMarker(marker)
            if mk["markerType"] == "KinematicTreeRigid":
                return Point(order.index(int(mk["objectNumber"])), int(mk["linkNumber"]),
                             tuple(float(v) for v in mk["localPosition"]))
            body = mbs.GetObject(int(mk["bodyNumber"]))
            if mk["markerType"] == "BodyPosition" and body["objectType"] == "Ground":
                return Point(-1, -1, tuple(float(a) + float(b) for a, b in
                                           zip(body["referencePosition"], mk["localPosition"])))
            raise NotCovered(f"marker type {mk['markerType']}")
        springs = []
        for number in system.connectors.values():
            item = mbs.GetObject(number)
            if item["objectType"] != "ConnectorSpringDamper" or not item["activeConnector"] or \
                    item["springForceUserFunction"] != 0:
                raise NotCovered(f"connector {item['objectType']}")
            springs.append(Spring(tuple(point(k) for k in item["markerNumbers"]), float(item["referenceLength"]),
                                  float(item["stiffness"]), float(item["damping"]), float(item["force"]),
                                  float(item["velocityOffset"])))
        knuckles = tuple(point(k) for k in system.markers.knuckles)
        if any(p.local != (0.0, 0.0, 0.0) for p in knuckles):
            raise NotCovered("knuckle markers off the link origins")
        return cls(trees, knuckles, tuple(springs), system.layout.n_mech, forces.stage_constants,
                   forces.stage_tables)

    def split(self) -> tuple[tuple, np.ndarray]:
        return self._split

    @functools.cached_property
    def _split(self) -> tuple[tuple, np.ndarray]:
        """(structure, numbers): what selects the equations' code paths, hashable, and the axle's numbers that
        enter them only as values (offsets, masses, inertias, stiffnesses, the user function's constants).  Two
        systems with equal structures have one graph, whose numbers are an input (:meth:`with_numbers`).

        A number is structural where the equations branch on it: integers (joint kinds, parents, coordinate
        indices), the constants at :data:`STRUCTURAL_CONSTANTS`, and every value that is exactly 0 or +-1 (a
        massless link is skipped, a zero roll-axis slope drops its terms, unit entries of joint rotations fold
        away: the graph stays as small as one built with constants).  A value that moves onto 0 or +-1 gives a
        new structure, so a new graph, never a wrong one."""
        numbers: list[float] = []

        def slot(x: float):
            numbers.append(x)
            return None
        d = _map_numbers(self, slot)
        return (d.trees, d.knuckles, d.springs, d.m, tuple(d.constants), np.shape(self.tables)), np.array(numbers)

    def with_numbers(self, P) -> "TwinData":
        """This data with :meth:`split`'s numbers replaced, in the same order, by the entries of P (the graph's
        symbols); the load tables stay (the twin reads their rows as inputs)."""
        it = iter(range(P.shape[0]))
        return _map_numbers(self, lambda x: P[next(it)])


def _structural_constants() -> frozenset[int]:
    """Indices of the compiled stage's constants that are switches, coordinate indices or table sizes."""
    cs = compiled_stage
    index = set(range(cs.I_VERT + 1))
    for w in cs.WHEELS:
        index |= {w + cs.EL + i for i in range(8, 13)} | {w + cs.SLIP + 4, w + cs.SLIP + 5}
        index |= {w + cs.TABLE + i for i in (0, 3, 4, 5, 6, 7)}
    return frozenset(index)


STRUCTURAL_CONSTANTS = _structural_constants()


# A geometric value this small is a zero that rounding left (a rotated offset's 1.7e-18 m on one machine, 0.0 on
# another): it is taken as 0 so that the structure, and with it the graph, does not depend on rounding.
ROUNDING_ZERO = 1e-14


def _structural(x: float) -> bool:
    return x == 1.0 or x == -1.0 or abs(x) < ROUNDING_ZERO


def _structure_value(x: float) -> float:
    return 0.0 if abs(x) < ROUNDING_ZERO else x


def _map_numbers(value, slot):
    """``value`` with each non-structural float replaced by ``slot(float)`` (:meth:`TwinData.split`), in a fixed
    order; the constants array becomes a list."""
    if isinstance(value, TwinData):
        fields = {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
        out = {k: _map_numbers(v, slot) for k, v in fields.items() if k not in ("constants", "tables")}
        c = [float(x) for x in value.constants]
        out["constants"] = [x if i in STRUCTURAL_CONSTANTS else _structure_value(x) if _structural(x) else slot(x)
                            for i, x in enumerate(c)]
        out["tables"] = value.tables
        return dataclasses.replace(value, **out)
    if dataclasses.is_dataclass(value):
        return type(value)(*(_map_numbers(getattr(value, f.name), slot) for f in dataclasses.fields(value)))
    if isinstance(value, tuple):
        return tuple(_map_numbers(v, slot) for v in value)
    if isinstance(value, float) and not isinstance(value, bool):
        return _structure_value(value) if _structural(value) else slot(value)
    return value


# --- 3-vectors and 3x3 matrices as tuples ------------------------------------------------------------------------
def _mv(A, v):
    return tuple(A[i][0] * v[0] + A[i][1] * v[1] + A[i][2] * v[2] for i in range(3))


def _mtv(A, v):
    return tuple(A[0][i] * v[0] + A[1][i] * v[1] + A[2][i] * v[2] for i in range(3))


def _mm(A, B):
    return tuple(tuple(A[i][0] * B[0][j] + A[i][1] * B[1][j] + A[i][2] * B[2][j] for j in range(3))
                 for i in range(3))


def _add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def _sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _rotation(axis: int, angle, ops):
    sin, cos = ops[0], ops[1]
    c, s = cos(angle), sin(angle)
    if axis == 0:
        return ((1.0, 0.0, 0.0), (0.0, c, -s), (0.0, s, c))
    if axis == 1:
        return ((c, 0.0, s), (0.0, 1.0, 0.0), (-s, 0.0, c))
    return ((c, -s, 0.0), (s, c, 0.0), (0.0, 0.0, 1.0))


_UNIT = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def link_motion(tree: Tree, q, qd, ops) -> list:
    """(R, o, omega, v_o) of every link at the tree state: rotation (rows, link -> world), origin, angular velocity
    and the origin's velocity (world)."""
    out = []
    for i, (kind, axis) in enumerate(tree.kinds):
        p = tree.parents[i]
        Rp, op, wp, vp = out[p] if p >= 0 else (_UNIT, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        RA = _mm(Rp, tree.rotations[i])
        a = RA[0][axis], RA[1][axis], RA[2][axis]       # the joint axis (world)
        if kind == "R":
            R = _mm(RA, _rotation(axis, q[i], ops))
            o = _add(op, _mv(Rp, tree.offsets[i]))
            w = _add(wp, tuple(qd[i] * x for x in a))
            v = _add(vp, _cross(wp, _sub(o, op)))
        else:
            R = RA
            o = _add(_add(op, _mv(Rp, tree.offsets[i])), tuple(q[i] * x for x in a))
            w = wp
            v = _add(_add(vp, _cross(wp, _sub(o, op))), tuple(qd[i] * x for x in a))
        out.append((R, o, w, v))
    return out


def kinetic_energy(tree: Tree, q, qd, ops):
    """The links' kinetic energy (translation of the centre of mass, rotation about it)."""
    total = 0.0
    for (R, o, w, v), m, com, J in zip(link_motion(tree, q, qd, ops), tree.masses, tree.coms, tree.inertias):
        if isinstance(m, float) and m == 0.0:     # a massless link (a structural zero, TwinData.split)
            continue
        r = _mv(R, com)
        vc = _add(v, _cross(w, r))
        wl = _mtv(R, w)
        total = total + 0.5 * m * _dot(vc, vc) + 0.5 * _dot(wl, _mv(J, wl))
    return total


def _point_motion(point: Point, motions) -> tuple:
    if point.tree < 0:
        return point.local, (0.0, 0.0, 0.0)
    R, o, w, v = motions[point.tree][point.link]
    r = _mv(R, point.local)
    return _add(o, r), _add(v, _cross(w, r))


def applied_forces(data: TwinData, q, qd, speed, ops, lookup, tables=None) -> tuple:
    """(ok, generalized forces on the tree's m + 2 coordinates): the joints' P/D control, the spring-dampers and
    the force user function (:func:`~mbs_shimmy.compiled_stage.stage_terms`); ``ok`` False where the user function
    would leave the load table (the compiled stage hands such states to Python).  ``lookup`` reads the load
    tables ``tables`` (default :attr:`TwinData.tables`) as :func:`~mbs_shimmy.compiled_stage.table_row` does."""
    n = data.m + 2
    motions = [link_motion(t, q, qd, ops) for t in data.trees]
    tree = data.trees[0]
    Q = [tree.p_control[i] * (tree.q_offsets[i] - q[i]) + tree.d_control[i] * (tree.v_offsets[i] - qd[i])
         for i in range(n)]
    for s in data.springs:
        (p0, v0), (p1, v1) = (_point_motion(e, motions) for e in s.ends)
        d = _sub(p1, p0)
        L = ops[3](_dot(d, d))
        u = tuple(x / L for x in d)
        f = s.stiffness * (L - s.length) + s.damping * (_dot(u, _sub(v1, v0)) - s.velocity_offset) + s.force
        # virtual power: the ends' velocities are linear in q', column j is their motion at q' = e_j
        for j in range(n):
            unit = [0.0] * n
            unit[j] = 1.0
            geometry = [link_motion(t, q, unit, ops) for t in data.trees]
            (_, u0), (_, u1) = (_point_motion(e, geometry) for e in s.ends)
            Q[j] = Q[j] - f * _dot(u, _sub(u1, u0))
    poses = []
    for k in data.knuckles:
        R, o, _, _ = motions[k.tree][k.link]
        poses += [(R[0][0], R[0][1], R[0][2], R[1][0], R[1][1], R[1][2], R[2][0], R[2][1], R[2][2]), o]
    c = data.constants
    ok, Qp, Q1, Q2, Qy, Qz, ad1, ad2 = compiled_stage.stage_terms(
        c, data.tables if tables is None else tables, poses[0], poses[1], poses[2], poses[3], q, qd, speed, 0.0, ops, lookup)
    m = data.m
    ip, i1, i2 = int(c[compiled_stage.I_PSI]), int(c[compiled_stage.I_TH1]), int(c[compiled_stage.I_TH2])
    ilat, ivert = int(c[compiled_stage.I_LAT]), int(c[compiled_stage.I_VERT])
    alignment = c[compiled_stage.ALIGNMENT:compiled_stage.ALIGNMENT + m + 2]
    user = list(alignment)
    user[ip] = user[ip] + Qp
    user[i1] = user[i1] + Q1
    user[i2] = user[i2] + Q2
    if ilat >= 0:
        user[ilat] = user[ilat] + Qy
    if ivert >= 0:
        user[ivert] = user[ivert] + Qz
    user[m], user[m + 1] = ad1, ad2
    return ok, [a + b for a, b in zip(Q, user)]
