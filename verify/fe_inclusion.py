"""scikit-fem axisymmetric FE reference: a spherical inhomogeneity on the axis under an applied Hertz
pressure (independent of halfspace's equivalent inclusion method).

Axisymmetric elasticity in (r, z), z up, body z < 0 (depth = -z), P2 triangles, the r-weighted form of
verify/fe.py. a = 1, E_m = 1, nu = 0.3 in both phases, Hertz pressure p0 sqrt(1 - r^2) with
p0 = 2 E* a / (pi R), R = 10. The inhomogeneity: a sphere of radius 0.3 centred on the axis at depth
0.5, E_I = ratio * E_m (ratio 2 and 0.5). The mesh is uniform (spacing h) on r < 1.5, depth < 1.5 and
grows geometrically to the far faces at 50a, where the Boussinesq displacement of the total load is
prescribed (the inhomogeneity's own far field decays like a dipole, rho^-2, and is neglected: its
effect is measured by doubling the domain). The sphere's surface is not a mesh line: the modulus is
evaluated at the quadrature points (intorder 6), so the interface is resolved to O(h); the error of
the fine level is estimated by Richardson between h = 1/40, 1/80 (first order: the fine level's error
~ the difference). Stresses at points: L2 projection of the quadrature-point stresses onto P2, then
point evaluation (the points sit >= 0.17 from the interface).

Outputs per ratio: surface displacement u_3 (positive into the body) at r = 0, 1/3, 2/3, 1, 4/3; the
stresses (sigma_rr, sigma_tt, sigma_zz, sigma_rz; tension positive, z down: sigma_rz with the sign of
our sigma_13 at y = 0) at (r, depth) = (0, 1/2) inside, (1/3, 1/6) above and aside, (0, 7/6) below and
(2/3, 1/2) beside the sphere, all at least 0.17 from its surface (closer, the cell staircase of the
EIM and the smeared FE interface dominate). These points are cell centres of halfspace's grids with
2 Delta = a/15, a/21, a/27.
"""
import numpy as np
import scipy.sparse.linalg as spla
from skfem import (Basis, BilinearForm, ElementTriP2, ElementVector, FacetBasis, LinearForm, MeshTri, asm,
                   condense, solve)

from .fe import boussinesq, graded_axis, lame

NU = 0.3
A = 1.0
R_SPHERE = 10.0
INC_RADIUS = 0.3
INC_DEPTH = 0.5
SURFACE_R = np.array([0.0, 1 / 3, 2 / 3, 1.0, 4 / 3])
POINTS = np.array([[0.0, 0.5], [1 / 3, 1 / 6], [0.0, 7 / 6], [2 / 3, 0.5]])  # (r, depth)
LEVELS = (1 / 40, 1 / 80)


def mesh(h, extent):
    r = graded_axis(h, extent, 1.15, 1.5)
    zeta = graded_axis(h, extent, 1.15, 1.5)
    return MeshTri.init_tensor(r, -zeta[::-1])


def modulus(r, z, ratio):
    inside = r * r + (z + INC_DEPTH) ** 2 < INC_RADIUS ** 2
    return np.where(inside, ratio, 1.0)


def stiffness_form(ratio):
    """The r-weighted axisymmetric stiffness with the inhomogeneity's modulus at the quadrature points."""
    @BilinearForm
    def stiffness(u, v, w):
        r = w.x[0]
        lam, mu = lame(modulus(r, w.x[1], ratio))
        eu = (u.grad[0][0], u.grad[1][1], u.value[0] / r, u.grad[0][1] + u.grad[1][0])
        ev = (v.grad[0][0], v.grad[1][1], v.value[0] / r, v.grad[0][1] + v.grad[1][0])
        tu, tv = eu[0] + eu[1] + eu[2], ev[0] + ev[1] + ev[2]
        return (lam * tu * tv + 2 * mu * (eu[0] * ev[0] + eu[1] * ev[1] + eu[2] * ev[2])
                + mu * eu[3] * ev[3]) * 2 * np.pi * r
    return stiffness


def solve_ratio(h, ratio, extent=50.0):
    m = mesh(h, extent)
    e = ElementVector(ElementTriP2())
    basis = Basis(m, e, intorder=6)

    stiffness = stiffness_form(ratio)
    K = asm(stiffness, basis)
    e_star = 1.0 / (1 - NU * NU)
    p0 = 2 * e_star * A / (np.pi * R_SPHERE)
    fb = FacetBasis(m, e, facets=m.facets_satisfying(lambda p: np.isclose(p[1], 0.0)), intorder=8)

    @LinearForm
    def load(v, w):
        r = w.x[0]
        return -p0 * np.sqrt(np.clip(1 - r * r / (A * A), 0, None)) * v.value[1] * 2 * np.pi * r

    f = asm(load, fb)
    total = 2 * np.pi * p0 * A * A / 3
    x = basis.zeros()
    loc = basis.doflocs
    axis = basis.get_dofs(lambda p: np.isclose(p[0], 0.0))
    outer = basis.get_dofs(lambda p: np.isclose(p[0], extent) | np.isclose(p[1], -extent))
    outer_r = np.concatenate([outer.nodal["u^1"], outer.facet["u^1"]])
    outer_z = np.concatenate([outer.nodal["u^2"], outer.facet["u^2"]])
    x[outer_r], _ = boussinesq(loc[0, outer_r], loc[1, outer_r], total)
    _, x[outer_z] = boussinesq(loc[0, outer_z], loc[1, outer_z], total)
    D = np.unique(np.concatenate([axis.nodal["u^1"], axis.facet["u^1"], outer_r, outer_z]))
    x = solve(*condense(K, f, x=x, D=D), solver=lambda A_, b_: spla.spsolve(A_.tocsc(), b_))
    # Surface displacement u_3 = -u_z at the requested radii.
    surf = np.vstack([SURFACE_R, np.zeros_like(SURFACE_R)])
    uz = basis.probes(surf) @ x
    u3 = -uz.reshape(2, -1)[1] if uz.size == 2 * SURFACE_R.size else None
    if u3 is None:
        raise RuntimeError("unexpected probe layout")
    # Stresses: quadrature-point values projected on P2, then probed.
    sb = basis.with_element(ElementTriP2())
    u = basis.interpolate(x)
    r = basis.mapping.F(basis.X)[0]
    z = basis.mapping.F(basis.X)[1]
    lam, mu = lame(modulus(r, z, ratio))
    err = u.grad[0][0]
    ezz = u.grad[1][1]
    ett = u.value[0] / r
    grz = u.grad[0][1] + u.grad[1][0]
    tr = err + ezz + ett
    stresses = {"stress_rr": lam * tr + 2 * mu * err, "stress_tt": lam * tr + 2 * mu * ett,
                "stress_zz": lam * tr + 2 * mu * ezz, "stress_rz": -mu * grz}
    pts = np.vstack([POINTS[:, 0], -POINTS[:, 1]])
    probe = sb.probes(pts)
    out = {"u3": u3}
    for name, qp in stresses.items():
        out[name] = probe @ sb.project(qp)
    return out


def generate():
    cases = []
    for ratio in (2.0, 0.5):
        sols = [solve_ratio(h, ratio) for h in LEVELS]
        fine, coarse = sols[1], sols[0]
        wide = solve_ratio(LEVELS[0], ratio, extent=100.0)
        arrays = {"surface_r": SURFACE_R, "points": POINTS.reshape(-1)}
        attrs = {"ratio": ratio, "nu": NU, "E_matrix": 1.0, "contact_radius": A, "sphere_radius": R_SPHERE,
                 "inclusion_radius": INC_RADIUS, "inclusion_depth": INC_DEPTH, "mesh_h": LEVELS[1],
                 "p0": 2 / (1 - NU * NU) / (np.pi * R_SPHERE),
                 "layout": "points: (4, 2) r, depth; stress_*: at the points; u3 at surface_r",
                 "description": "Hertz pressure applied on a half-space (50a, Boussinesq far field) with a "
                                "spherical inhomogeneity on the axis; P2 axisymmetric FE, non-conforming "
                                "interface (modulus at quadrature points)"}
        for key in ("u3", "stress_rr", "stress_tt", "stress_zz", "stress_rz"):
            arrays[key] = fine[key]
            attrs[f"discretization_error_{key}"] = float(np.max(np.abs(fine[key] - coarse[key])))
            attrs[f"truncation_error_{key}"] = float(np.max(np.abs(wide[key] - coarse[key])))
        cases.append({"case": f"fe_inclusion_ratio{ratio:g}", "arrays": arrays, "attrs": attrs})
    return cases + generate_contact()


# ---------------------------------------------------------------------------------------------
# Frictionless contact of a rigid sphere with the half-space containing the same inhomogeneity.

CONTACT_LEVELS = (1 / 40, 1 / 60)
DEPTH = A * A / R_SPHERE  # the homogeneous Hertz approach for a = 1


def contact_solve(h, ratio, extent=50.0):
    """Rigid sphere R = 10 pressed to the depth delta = a^2/R (the homogeneous contact radius is a):
    the active set of surface DOFs with prescribed u_z = -(delta - r^2/2R) is adjusted until every
    contact DOF carries a compressive reaction and no free DOF penetrates (a Signorini active-set
    iteration, one contact DOF at a time at the edge). The far faces carry the Boussinesq field of
    the current force (iterated with the active set)."""
    m = mesh(h, extent)
    e = ElementVector(ElementTriP2())
    basis = Basis(m, e, intorder=6)

    stiffness = stiffness_form(ratio)
    K = asm(stiffness, basis).tocsr()
    loc = basis.doflocs
    top = basis.get_dofs(lambda p: np.isclose(p[1], 0.0))
    axis = basis.get_dofs(lambda p: np.isclose(p[0], 0.0))
    outer = basis.get_dofs(lambda p: np.isclose(p[0], extent) | np.isclose(p[1], -extent))
    uz_top = np.concatenate([top.nodal["u^2"], top.facet["u^2"]])
    uz_top = uz_top[np.argsort(loc[0, uz_top])]
    r_top = loc[0, uz_top]
    outer_r = np.concatenate([outer.nodal["u^1"], outer.facet["u^1"]])
    outer_z = np.concatenate([outer.nodal["u^2"], outer.facet["u^2"]])
    axis_r = np.concatenate([axis.nodal["u^1"], axis.facet["u^1"]])
    n_contact = int(np.searchsorted(r_top, A * (1 + 1e-9), side="right"))
    force = 2 * np.pi * (2 / (1 - NU * NU) / (np.pi * R_SPHERE)) * A * A / 3
    f = basis.zeros()
    seen = set()
    for _ in range(200):
        x = basis.zeros()
        contact = uz_top[:n_contact]
        x[contact] = -(DEPTH - loc[0, contact] ** 2 / (2 * R_SPHERE))
        x[outer_r], _ = boussinesq(loc[0, outer_r], loc[1, outer_r], force)
        _, x[outer_z] = boussinesq(loc[0, outer_z], loc[1, outer_z], force)
        D = np.unique(np.concatenate([axis_r, outer_r, outer_z, contact]))
        x = solve(*condense(K, f, x=x, D=D), solver=lambda A_, b_: spla.spsolve(A_.tocsc(), b_))
        reaction = -(K @ x - f)
        new_force = float(np.sum(reaction[contact]))
        u3 = -x[uz_top]
        gap = r_top ** 2 / (2 * R_SPHERE) - DEPTH + u3
        # Reactions of the edge DOFs: a tensile one leaves the contact; a penetrating free DOF enters.
        r_contact = reaction[contact]
        state = (n_contact, round(new_force, 12))
        if r_contact[-1] < 0 and n_contact > 1:
            n_contact -= 1
        elif n_contact < len(uz_top) and gap[n_contact] < 0:
            n_contact += 1
        elif abs(new_force - force) > 1e-10 * abs(new_force):
            pass
        else:
            break
        force = new_force
        if state in seen and abs(new_force - force) <= 1e-10 * abs(new_force):
            break
        seen.add(state)
    contact = uz_top[:n_contact]
    from .fe import pressure_from_reactions
    pr, p = pressure_from_reactions(m, e, reaction, contact, loc)
    edge = 0.5 * (r_top[n_contact - 1] + r_top[min(n_contact, len(r_top) - 1)])
    return {"force": new_force, "contact_radius": edge, "contact_radius_resolution": 0.5 * (
        r_top[min(n_contact, len(r_top) - 1)] - r_top[n_contact - 1]),
        "p_centre": float(p[0]), "p_max": float(np.max(p[pr < 0.95 * edge])),
        "u3_centre": float(u3[0])}


def generate_contact():
    cases = []
    for ratio in (2.0, 0.5):
        sols = [contact_solve(h, ratio) for h in CONTACT_LEVELS]
        fine, coarse = sols[1], sols[0]
        arrays = {"values": np.array([fine["force"], fine["contact_radius"], fine["p_centre"], fine["p_max"]])}
        attrs = {"ratio": ratio, "nu": NU, "E_matrix": 1.0, "sphere_radius": R_SPHERE, "depth": DEPTH,
                 "inclusion_radius": INC_RADIUS, "inclusion_depth": INC_DEPTH, "mesh_h": CONTACT_LEVELS[1],
                 "contact_radius_resolution": fine["contact_radius_resolution"],
                 "layout": "values: force, contact radius, p(0), p_max (over r < 0.95 c)",
                 "description": "frictionless rigid sphere (R = 10) pressed to delta = 0.1 on a half-space "
                                "with a spherical inhomogeneity on the axis; P2 axisymmetric FE with a "
                                "Signorini active set on the surface DOFs"}
        for k in ("force", "contact_radius", "p_centre", "p_max"):
            attrs[f"discretization_error_{k}"] = float(abs(fine[k] - coarse[k]))
        cases.append({"case": f"fe_inclusion_contact_ratio{ratio:g}", "arrays": arrays, "attrs": attrs})
    return cases
