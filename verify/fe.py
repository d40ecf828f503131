"""scikit-fem axisymmetric finite-element references (independent of halfspace).

Axisymmetric linear elasticity in (r, z), z up, the body in -H < z < 0, its surface z = 0:
strains (u_r,r, u_z,z, u_r/r, u_r,z + u_z,r), weight 2πr, quadratic triangles (P2) on a tensor mesh
graded toward the contact edge r = a (a node there) and toward the surface. a = 1, E (or E0) = 1,
ν = 0.3, z0 = 1, sphere radius R = 10.

Cases
  hertz_load     Hertz pressure p0 √(1 - r²) applied (homogeneous) -> surface displacement u(r).
  sphere_k{k}    sphere pressed to the depth δ whose contact radius is a = 1 (δ = a²/((1+k)R)), the
                 mixed problem (prescribed u_z on r < a, traction-free outside) for E(z) = E0 (-z/z0)^k,
                 k = 0, +0.3, -0.3 -> contact pressure from the reactions, force, surface displacement.

Far boundary (r = 50a, z = -50a): the Boussinesq point-load displacement for the applied total force
(homogeneous), which makes the truncated block behave like a half-space; for the graded cases, whose
interior Green's function is not available here, the outer faces are fixed and the truncation error is
estimated by doubling the domain. Discretization error: Richardson between meshes h = a/16 and a/32
(P2: displacement O(h³), pressure from the reactions O(h²)). Both estimates are stored with the case.
"""
import math

import numpy as np
import scipy.sparse.linalg as spla
from skfem import (Basis, BilinearForm, ElementTriP2, ElementVector, FacetBasis, LinearForm,
                   MeshTri, asm, condense, solve)

NU = 0.3
R_SPHERE = 10.0
A = 1.0


def graded_axis(h, extent, growth, fine_end):
    """Nodes on [0, extent]: spacing h up to fine_end (a node there), then growing geometrically."""
    n_fine = max(1, round(fine_end / h))
    nodes = list(np.linspace(0.0, fine_end, n_fine + 1))
    step = fine_end / n_fine
    while nodes[-1] < extent:
        step *= growth
        nodes.append(min(nodes[-1] + step, extent))
        if extent - nodes[-1] < 0.5 * step:
            nodes[-1] = extent
    return np.array(nodes)


def surface_layers(h, first, growth=1.25):
    """Depths 0, first, first·g, … up to spacing h: geometric refinement toward the surface."""
    nodes = [0.0]
    step = first
    while step < h:
        nodes.append(nodes[-1] + step)
        step *= growth
    return np.array(nodes)


def mesh(h, extent, surface_first=None):
    r = graded_axis(h, extent, 1.12, 1.25 * A)
    if surface_first is None:
        zeta = graded_axis(h / 2, extent, 1.12, 0.5 * A)
    else:
        # Graded media: E ~ ζ^k is singular or vanishing at the surface; resolve it geometrically.
        layers = surface_layers(h / 2, surface_first)
        rest = graded_axis(h / 2, extent - layers[-1], 1.12, 0.5 * A) + layers[-1]
        zeta = np.concatenate([layers[:-1], rest])
    z = -zeta[::-1]
    m = MeshTri.init_tensor(r, z)
    return m


def lame(E):
    return E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))


def stiffness_form(k):
    @BilinearForm
    def form(u, v, w):
        r = w.x[0]
        zeta = -w.x[1]
        E = zeta ** k if k != 0 else 1.0 + 0 * r
        lam, mu = lame(E)
        eu = (u.grad[0][0], u.grad[1][1], u.value[0] / r, u.grad[0][1] + u.grad[1][0])
        ev = (v.grad[0][0], v.grad[1][1], v.value[0] / r, v.grad[0][1] + v.grad[1][0])
        tu = eu[0] + eu[1] + eu[2]
        tv = ev[0] + ev[1] + ev[2]
        return (lam * tu * tv + 2 * mu * (eu[0] * ev[0] + eu[1] * ev[1] + eu[2] * ev[2])
                + mu * eu[3] * ev[3]) * 2 * np.pi * r
    return form


def boussinesq(r, z, force):
    """Point load `force` (into the body) at the origin of a homogeneous half-space: (u_r, u_z)."""
    G = 1.0 / (2 * (1 + NU))
    zeta = -z
    rho = np.sqrt(r * r + zeta * zeta)
    ur = force / (4 * np.pi * G) * (r * zeta / rho ** 3 - (1 - 2 * NU) * r / (rho * (rho + zeta)))
    uzeta = force / (4 * np.pi * G) * (zeta * zeta / rho ** 3 + 2 * (1 - NU) / rho)
    return ur, -uzeta


def solve_case(h, extent, k, mode, far="boussinesq", surface_first=None):
    """mode: 'load' (Hertz pressure applied) or 'depth' (sphere to depth δ, contact radius a)."""
    m = mesh(h, extent, surface_first)
    e = ElementVector(ElementTriP2())
    basis = Basis(m, e, intorder=6)
    K = asm(stiffness_form(k), basis)
    x = basis.zeros()
    f = basis.zeros()
    loc = basis.doflocs
    top = basis.get_dofs(lambda p: np.isclose(p[1], 0.0))
    axis = basis.get_dofs(lambda p: np.isclose(p[0], 0.0))
    outer = basis.get_dofs(lambda p: np.isclose(p[0], extent) | np.isclose(p[1], -extent))
    uz_top = np.concatenate([top.nodal["u^2"], top.facet["u^2"]])
    D = [axis.nodal["u^1"], axis.facet["u^1"]]
    e_star = 1.0 / (1 - NU * NU)
    if mode == "load":
        p0 = 2 * e_star * A / (np.pi * R_SPHERE)
        fb = FacetBasis(m, e, facets=m.facets_satisfying(lambda p: np.isclose(p[1], 0.0)), intorder=8)

        @LinearForm
        def load(v, w):
            r = w.x[0]
            p = p0 * np.sqrt(np.clip(1 - r * r / (A * A), 0, None))
            return -p * v.value[1] * 2 * np.pi * r
        f = asm(load, fb)
        total = 2 * np.pi * p0 * A * A / 3
    else:
        delta = A * A / ((1 + k) * R_SPHERE)
        contact = uz_top[loc[0, uz_top] <= A * (1 + 1e-12)]
        x[contact] = -(delta - loc[0, contact] ** 2 / (2 * R_SPHERE))
        D.append(contact)
        total = None
    outer_r = np.concatenate([outer.nodal["u^1"], outer.facet["u^1"]])
    outer_z = np.concatenate([outer.nodal["u^2"], outer.facet["u^2"]])
    if far == "boussinesq":
        if total is None:
            # The force is not known before the solve: iterate on it (converges in a few steps).
            total = graded_hertz_force(k, delta)
        ur, _ = boussinesq(loc[0, outer_r], loc[1, outer_r], total)
        _, uz = boussinesq(loc[0, outer_z], loc[1, outer_z], total)
        x[outer_r], x[outer_z] = ur, uz
    D += [outer_r, outer_z]
    D = np.unique(np.concatenate(D))
    x = solve(*condense(K, f, x=x, D=D), solver=lambda A_, b_: spla.spsolve(A_.tocsc(), b_))
    # Surface values at the surface DOF locations (nodes and edge midpoints), sorted by r.
    order = np.argsort(loc[0, uz_top])
    dofs = uz_top[order]
    r = loc[0, dofs]
    u_surface = -x[dofs]
    out = {"r": r, "displacement": u_surface}
    if mode == "depth":
        # K x − f at the prescribed DOFs is the force the indenter applies to the body (downward,
        # negative z); the compressive contact pressure is its negative.
        reaction = -(K @ x - f)
        contact = dofs[r <= A * (1 + 1e-12)]
        out["force"] = float(np.sum(reaction[contact]))
        out["pressure_r"], out["pressure"] = pressure_from_reactions(m, e, reaction, contact, loc)
    return out


def pressure_from_reactions(m, e, reaction, contact_dofs, loc):
    """Nodal pressure p_h on the contact facets from the consistent reactions R_i = ∫ p φ_i 2πr dr:
    solve the facet mass system M p_h = R on the contact DOFs."""
    fb = FacetBasis(m, e, facets=m.facets_satisfying(lambda p: np.isclose(p[1], 0.0) & (p[0] <= A + 1e-12)),
                    intorder=8)

    @BilinearForm
    def mass(u, v, w):
        return u.value[1] * v.value[1] * 2 * np.pi * w.x[0]
    M = asm(mass, fb).tocsr()[contact_dofs][:, contact_dofs]
    p = spla.spsolve(M.tocsc(), reaction[contact_dofs])
    r = loc[0, contact_dofs]
    order = np.argsort(r)
    return r[order], p[order]


def graded_hertz_force(k, delta):
    """Closed-form graded Hertz force (docs/theory-mdr.md#graded-closed-forms) for the far-field estimate only."""
    from .quadrature import c_n
    a = math.sqrt((1 + k) * R_SPHERE * delta)
    cn = c_n(k) if k != 0 else 1 / (1 - NU * NU)
    return 4 * cn * a ** (3 + k) / ((1 + k) ** 2 * (3 + k) * R_SPHERE)


LEVELS = (1 / 16, 1 / 32)
EXTENTS = (200.0, 400.0)
SURFACE_FIRST = 1e-4
R_MAX_OUT = 3.0


def _common(r_fine, r_coarse, values_coarse):
    """Coarse values at the fine positions they share (nested meshes near the contact)."""
    idx = [np.argmin(np.abs(r_coarse - x)) for x in r_fine]
    ok = np.abs(r_coarse[idx] - r_fine) < 1e-12
    return ok, values_coarse[idx]


def _rel_l2(a, b):
    return float(np.sqrt(np.sum((a - b) ** 2) / np.sum(b ** 2)))


def depth_case(k):
    """Sphere (R = 10) to the depth that gives a = 1 in E(z) = (-z)^k: mixed BVP. Far faces fixed at
    L = 200 and 400; the truncation error, ~ L^-(1+k) like the far field, is extrapolated away
    (Richardson in L); the discretization error is estimated from h = a/16 against a/32."""
    delta = A * A / ((1 + k) * R_SPHERE)
    sols = {}
    for h in LEVELS:
        runs = [solve_case(h, L, k, "depth", far="fixed", surface_first=SURFACE_FIRST) for L in EXTENTS]
        for run in runs:
            near = run["r"] <= R_MAX_OUT
            run["r"], run["displacement"] = run["r"][near], run["displacement"][near]
        # Both extents share the mesh near the contact (the grading starts at the same nodes).
        assert np.array_equal(runs[0]["r"], runs[1]["r"])
        assert np.array_equal(runs[0]["pressure_r"], runs[1]["pressure_r"])
        q = (EXTENTS[1] / EXTENTS[0]) ** (1 + k)
        ext = {}
        for key in ("displacement", "pressure"):
            ext[key] = runs[1][key] + (runs[1][key] - runs[0][key]) / (q - 1)
        ext["force"] = runs[1]["force"] + (runs[1]["force"] - runs[0]["force"]) / (q - 1)
        ext["truncation_pressure"] = _rel_l2(runs[1]["pressure"], ext["pressure"])
        ext["truncation_force"] = abs(runs[1]["force"] / ext["force"] - 1)
        ext["truncation_displacement"] = float(np.max(np.abs(runs[1]["displacement"] - ext["displacement"])) / delta)
        ext["r"], ext["pressure_r"] = runs[1]["r"], runs[1]["pressure_r"]
        sols[h] = ext
    fine, coarse = sols[LEVELS[1]], sols[LEVELS[0]]
    ok, pc = _common(fine["pressure_r"], coarse["pressure_r"], coarse["pressure"])
    inner = ok & (fine["pressure_r"] < 0.95 * A)
    # Richardson for O(h²) pressure: error of the fine level ≈ |fine − coarse| / 3.
    disc_p = _rel_l2(fine["pressure"][inner], pc[inner]) / 3
    sel_u = fine["r"] <= R_MAX_OUT
    ok_u, uc = _common(fine["r"][sel_u], coarse["r"], coarse["displacement"])
    disc_u = float(np.max(np.abs(fine["displacement"][sel_u][ok_u] - uc[ok_u]))) / delta / 7
    keep_p = fine["pressure_r"] <= A
    return {
        "case": f"fe_sphere_k{k:+.1f}",
        "arrays": {"r": fine["r"][sel_u], "displacement": fine["displacement"][sel_u],
                   "pressure_r": fine["pressure_r"][keep_p], "pressure": fine["pressure"][keep_p]},
        "attrs": {"k": k, "nu": NU, "E0": 1.0, "z0": 1.0, "sphere_radius": R_SPHERE, "contact_radius": A,
                  "depth": delta, "force": fine["force"], "mesh_h": LEVELS[1], "extents": list(EXTENTS),
                  "surface_first_layer": SURFACE_FIRST,
                  "discretization_error_pressure_l2": disc_p,
                  "discretization_error_displacement": disc_u,
                  "truncation_correction_pressure_l2": fine["truncation_pressure"],
                  "truncation_correction_force": fine["truncation_force"],
                  "truncation_correction_displacement": fine["truncation_displacement"],
                  "units": "dimensionless: a = 1, E0 = 1 (E(z) = E0 (-z/z0)^k)",
                  "description": "mixed BVP: u_z prescribed on r < a, traction-free outside; pressure from "
                                 "the reactions (compare over r < 0.95a: it oscillates at the edge)"},
    }


def load_case():
    """Hertz pressure (R = 10, a = 1, E = 1) applied; Boussinesq far field on the outer faces."""
    sols = {h: solve_case(h, 50.0, 0.0, "load", far="boussinesq") for h in LEVELS}
    fine, coarse = sols[LEVELS[1]], sols[LEVELS[0]]
    delta = A * A / R_SPHERE
    sel = fine["r"] <= R_MAX_OUT
    ok, uc = _common(fine["r"][sel], coarse["r"], coarse["displacement"])
    disc = float(np.max(np.abs(fine["displacement"][sel][ok] - uc[ok]))) / delta / 7
    # Truncation: the same with the domain doubled.
    wide = solve_case(LEVELS[0], 100.0, 0.0, "load", far="boussinesq")
    ok2, uw = _common(coarse["r"][coarse["r"] <= R_MAX_OUT], wide["r"], wide["displacement"])
    trunc = float(np.max(np.abs(coarse["displacement"][coarse["r"] <= R_MAX_OUT][ok2] - uw[ok2]))) / delta
    return {
        "case": "fe_hertz_load",
        "arrays": {"r": fine["r"][sel], "displacement": fine["displacement"][sel]},
        "attrs": {"k": 0.0, "nu": NU, "E": 1.0, "sphere_radius": R_SPHERE, "contact_radius": A,
                  "depth": delta, "mesh_h": LEVELS[1], "extent": 50.0,
                  "discretization_error_displacement": disc, "truncation_error_displacement": trunc,
                  "units": "dimensionless: a = 1, E = 1",
                  "description": "Hertz pressure p0 sqrt(1 - r^2) applied, Boussinesq displacement on the "
                                 "outer faces; surface displacement (positive into the body)"},
    }


def generate():
    return [load_case()] + [depth_case(k) for k in (0.0, 0.3, -0.3)]
