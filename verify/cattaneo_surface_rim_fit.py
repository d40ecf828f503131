"""A probe, not a fixture generator (docs/fatigue.md, "Where the surface error sits"): does
subtracting a fitted Hertzian edge make the Cattaneo–Mindlin cycle's SURFACE stresses converge?

The solver's cycle tractions (per grid, dumped by
`DUMP_TRACTIONS=DIR cargo test -p halfspace --test fixtures_cattaneo_fatigue surface_error_sources
-- --nocapture`: DIR/tractions_N.f64 = [increment][p, q1, q2][cell] in Pa, DIR/tractions_N.json)
are split into a fitted Hertzian part and a residual:

* the pressure p_H = p0' sqrt(1 - r^2/a'^2) about the pressure's centroid, with a'^2 = (5/2) <r^2>_p
  (the second moment of a Hertzian pressure is 2a^2/5) and p0' = 3W/(2 pi a'^2);
* the shear k(t) p_H along x, k the least-squares ratio q1/p_H over a' - 4h < r < a' - h (the slip
  zone at the rim, where |q| = mu p);
* the residual t - t_fit at the cell centres, set to zero within `ZERO_BAND` cells of r = a' (the
  fit replaces the solver's rim cells), evaluated piecewise constant by Love's rectangle
  stresses at z = 0 (docs/theory-sam.md#love-rectangle-stresses, ported below);
* the fitted part by its closed-form surface stresses (Johnson 1985 Eqs. 3.41, 3.42; the shear
  by Cerruti's surface displacements, verify/cattaneo_fatigue_surface.py).

Printed per grid: the piecewise-constant evaluation's error at the rim cells (reproduces the Rust
test's numbers), the fit's a', p0', and for the fit the largest path error and Crossland's index
(f-1 = 400 MPa, t-1 = 280 MPa; minimum ball by Badoiu–Clarkson iterations, ~1e-4) at the
fixture's fine points (datasets/cattaneo_fatigue_surface.json), for the solver's tractions and for
the exact Mindlin–Deresiewicz tractions sampled at the same cell centres.
Run: python3 verify/cattaneo_surface_rim_fit.py DIR  (numpy only; about a minute).
With --edges (python3 verify/cattaneo_surface_rim_fit.py --edges DIR [SUBCELLS]): method 2 below,
an edge-aware continuous reconstruction instead of the fit (a few minutes).
"""
import json
import pathlib
import sys

import numpy as np

NU, MU = 0.3, 0.3
G = 1 / (2 * (1 + NU))
C_STAR = 0.5 ** (1 / 3)
A_OVER_K = 1 - 0.5 ** (2 / 3)
ZERO_BAND = 1.5
ROOT = pathlib.Path(__file__).resolve().parent.parent


def md_traction(x, y, t):
    """The exact (p, q1) per p0 at (x, y)/a, increment t of the closed cycle (Johnson 1985 7.3)."""
    r2 = x * x + y * y

    def s(c):
        return np.sqrt(np.maximum(c * c - r2, 0.0))

    tt, sign = (t, 1.0) if t <= 20 else (t - 20, -1.0)
    b = np.sqrt(1 - tt / 10 * A_OVER_K / 2)
    return s(1.0), sign * MU * (-s(1.0) - s(C_STAR) + 2 * s(b))


def _rho_plus(rho, c, rest2):
    return np.where(c >= 0, rho + c, rest2 / np.where(rho - c == 0, 1, rho - c))


def _pressure_primitive(c1, c2):
    """Love's corner primitive of a unit pressure at z = 0 (the z -> 0 limit of the Rust kernel)."""
    rho = np.sqrt(c1 * c1 + c2 * c2)
    phi_z = -np.pi / 2 * np.sign(c1 * c2)
    k, zero = 1 / (2 * np.pi), np.zeros_like(c1)
    s11 = 2 * NU * phi_z - (1 - 2 * NU) * np.arctan(c2 / c1)
    s22 = 2 * NU * phi_z - (1 - 2 * NU) * np.arctan(c1 / c2)
    return k * np.array([s11, s22, phi_z, zero, zero, -(1 - 2 * NU) * np.log(rho)])


def _shear_primitive(c1, c2):
    """Love's corner primitive of a unit shear along +x at z = 0."""
    rho = np.sqrt(c1 * c1 + c2 * c2)
    l1, l2 = np.log(_rho_plus(rho, c1, c2 * c2)), np.log(_rho_plus(rho, c2, c1 * c1))
    k, zero = 1 / (2 * np.pi), np.zeros_like(c1)
    s11 = 2 * l2 + c2 / rho - (1 - 2 * NU) * c2 / rho
    s22 = 2 * NU * l2 - c2 / rho + (1 - 2 * NU) * c2 / rho
    s12 = l1 - c1 / rho + (1 - 2 * NU) * c1 / rho
    return k * np.array([s11, s22, zero, zero, -np.pi / 2 * np.sign(c1 * c2), s12])


def _corner(f, x1, x2, d):
    return sum(s1 * s2 * f(x1 + s1 * d, x2 + s2 * d) for s1, s2 in ((1, 1), (1, -1), (-1, 1), (-1, -1)))


def piecewise_constant_paths(tr, xc, yc, h, points):
    """Surface stress paths (M, 41, 6) per p0 of piecewise-constant tractions tr (41, 3, cells)."""
    out = []
    for x, y in points:
        kp = _corner(_pressure_primitive, x - xc, y - yc, h / 2)
        kq = _corner(_shear_primitive, x - xc, y - yc, h / 2)
        out.append(np.einsum("kn,tn->tk", kp, tr[:, 0]) + np.einsum("kn,tn->tk", kq, tr[:, 1]))
    return np.array(out)


def _v_f(r, inside):
    if inside:
        return np.pi**2 * (2 - r * r) / 4, np.pi**2 * (r * r - r**4 / 4) / 4
    t, asn = np.sqrt(r * r - 1), np.arcsin(1 / r)
    return np.pi / 2 * ((2 - r * r) * asn + t), np.pi / 2 * ((r * r - r**4 / 4) * asn + 0.75 * t + t**3 / 4)


def _shear_disp(x, y, inside):
    r2 = x * x + y * y
    r = np.sqrt(r2)
    v, f = _v_f(r, inside)
    w1 = f / r
    w2 = v - w1 / r
    wyy, wxy = w2 * y * y / r2 + w1 / r * x * x / r2, (w2 - w1 / r) * x * y / r2
    k = 1 / (2 * np.pi * G)
    return k * ((1 - NU) * v + NU * wyy), -k * NU * wxy


def hertz_shear_surface(x, y):
    """Surface stresses of the shear sqrt(1 - r^2) along +x (verify/cattaneo_fatigue_surface.py)."""
    inside, step = np.hypot(x, y) < 1, 1e-30
    gx = [np.imag(u) / step for u in _shear_disp(complex(x, step), complex(y), inside)]
    gy = [np.imag(u) / step for u in _shear_disp(complex(x), complex(y, step), inside)]
    exx, eyy, exy = gx[0], gy[1], 0.5 * (gy[0] + gx[1])
    out = np.zeros(6)
    out[0], out[1] = 2 * G * (exx + NU * eyy) / (1 - NU), 2 * G * (eyy + NU * exx) / (1 - NU)
    out[4], out[5] = -np.sqrt(max(1 - x * x - y * y, 0.0)), 2 * G * exy
    return out


def hertz_normal_surface(x, y):
    """Surface stresses of the pressure sqrt(1 - r^2) (Johnson 1985 Eqs. 3.41, 3.42)."""
    r2 = x * x + y * y
    r, s = np.sqrt(r2), np.sqrt(max(1 - r2, 0.0))
    a = (1 - 2 * NU) / (3 * r2) * (1 - s**3)
    sr = a - s if r < 1 else (1 - 2 * NU) / (3 * r2)
    st = -a - 2 * NU * s if r < 1 else -(1 - 2 * NU) / (3 * r2)
    c, sn = x / r, y / r
    out = np.zeros(6)
    out[0], out[1], out[2], out[5] = sr * c * c + st * sn * sn, sr * sn * sn + st * c * c, -s, (sr - st) * sn * c
    return out


def fitted_paths(tr, xc, yc, h, points):
    """The fitted Hertzian part in closed form + the residual piecewise constant (docstring)."""
    p = tr[:, 0]
    w = p.sum(1)
    xb, yb = (p * xc).sum(1) / w, (p * yc).sum(1) / w
    r2 = (xc - xb[:, None]) ** 2 + (yc - yb[:, None]) ** 2
    a = np.sqrt(2.5 * (p * r2).sum(1) / w)
    p0 = 3 * w * h * h / (2 * np.pi * a * a)
    ph = p0[:, None] * np.sqrt(np.maximum(1 - r2 / a[:, None] ** 2, 0))
    r = np.sqrt(r2)
    band = (r > a[:, None] - 4 * h) & (r < a[:, None] - h)
    k = (tr[:, 1] * ph * band).sum(1) / (ph * ph * band).sum(1)
    res = tr.copy()
    res[:, 0] -= ph
    res[:, 1] -= k[:, None] * ph
    res *= ~(np.abs(r - a[:, None]) < ZERO_BAND * h)[:, None, :]
    out = piecewise_constant_paths(res, xc, yc, h, points)
    for m, (x, y) in enumerate(points):
        for t in range(out.shape[1]):
            u, v = (x - xb[t]) / a[t], (y - yb[t]) / a[t]
            out[m, t] += p0[t] * (hertz_normal_surface(u, v) + k[t] * hertz_shear_surface(u, v))
    return out, a[0], p0[0]


def crossland(path, p0):
    """Crossland's index of a path (41, 6) per p0 (docs/fatigue.md Eq. F3), approximate ball."""
    s = path * p0
    sh = s[:, :3].sum(1) / 3
    d = s.copy()
    d[:, :3] -= sh[:, None]
    y = np.stack([np.sqrt(3) / 2 * d[:, 2], (d[:, 0] - d[:, 1]) / 2, d[:, 3], d[:, 4], d[:, 5]], 1) / 1e9
    c = y.mean(0)
    for i in range(4000):
        j = np.linalg.norm(y - c, axis=1).argmax()
        c = c + (y[j] - c) / (i + 2)
    f, t = 400e6, 280e6
    return (np.linalg.norm(y - c, axis=1).max() * 1e9 + (t - f / np.sqrt(3)) / (f / 3) * sh.max()) / t


def main(directory):
    fx = json.loads((ROOT / "datasets" / "cattaneo_fatigue_surface.json").read_text())
    fine_points = [(x + 1e-9, y + 1e-9) for x, y in fx["fine"]["points"]]  # off the cell edges
    fine_ref = np.array(fx["fine"]["stress"])
    for n in (32, 64, 128):
        meta = json.loads((pathlib.Path(directory) / f"tractions_{n}.json").read_text())
        p0 = meta["p0"]
        tr = np.fromfile(pathlib.Path(directory) / f"tractions_{n}.f64").reshape(41, 3, n * n) / p0
        h = 2 * meta["half"] / meta["a"]
        cell = np.arange(n * n)
        xc, yc = (cell // n + 0.5) * h - n * h / 2, (cell % n + 0.5) * h - n * h / 2
        exact = np.zeros_like(tr)
        for t in range(41):
            exact[t, 0], exact[t, 1] = md_traction(xc, yc, t)
        window = fx["grids"][str(n)]
        pts, ref = window["points"], np.array(window["stress"])
        rim = np.abs(np.hypot(*np.array(pts).T) - 1) < 1.5 * h
        pc = piecewise_constant_paths(tr, xc, yc, h, pts)
        print(f"{n}²: piecewise constant, rim cells max |Δσ|/p0 {np.abs(pc - ref)[rim].max():.3e}")
        for label, tractions in (("solver", tr), ("exact MD at the centres", exact)):
            got, a_fit, p0_fit = fitted_paths(tractions, xc, yc, h, fine_points)
            c_got = np.array([crossland(got[m], p0) for m in range(len(fine_points))])
            c_ref = np.array([crossland(fine_ref[m], p0) for m in range(len(fine_points))])
            print(f"{n}²: Hertz fit of the {label}: a' = {a_fit:.5f} a, p0' = {p0_fit:.5f} p0; fine points: "
                  f"max |Δσ|/p0 {np.abs(got - fine_ref).max():.3e}, max |ΔCrossland| "
                  f"{np.abs(c_got - c_ref).max():.3f}, Crossland max {c_got.max():.4f} at "
                  f"{np.round(fine_points[int(c_got.argmax())], 4).tolist()} (closed form {c_ref.max():.4f})",
                  flush=True)


# --- Method 2: an edge-aware continuous reconstruction (`--edges`) -----------------------------
# Per increment, the pressure is reconstructed as p = sqrt(max(0, P)) with P a local least-squares
# quadratic of p^2 over the contact cells of each cell's 7 x 7 neighbourhood (p^2 is smooth across
# a contact rim: 1 - r^2 for Hertz), and the shear along the rim's slip direction s as
# q = s (mu p - D), D = sqrt(max(0, Q)), Q the same fit of the slip deficit squared D^2 =
# (mu p - s q)^2 over the stick cells (smooth across the stick-slip boundary). The surface stress at
# a point x: every cell outside the square S of side 7h centred at x by its cell average of the
# reconstruction (8 x 8 midpoints; cells cut by S by the rectangles outside S), the square S by
# SUBCELLS x SUBCELLS subcells per cell width of the reconstruction, x a subcell centre (all by
# Love's rectangle stresses at z = 0).
SUBCELLS = 15

def _corner2(f,x1,x2,d1,d2):
    return sum(s1*s2*f(x1+s1*d1,x2+s2*d2) for s1,s2 in ((1,1),(1,-1),(-1,1),(-1,-1)))
def love(x,y,cx,cy,d1,d2):
    """(6, K) pressure and q1 kernels at point (x,y) for rectangles centred (cx,cy) half-widths d1,d2"""
    return _corner2(_pressure_primitive,x-cx,y-cy,d1,d2), _corner2(_shear_primitive,x-cx,y-cy,d1,d2)
def local_quadratic_fits(val, mask, n, h, xc, yc, rad=3):
    """per cell: LS quadratic (scaled basis) of val over masked cells in its (2rad+1)^2 neighbourhood,
    falling back to linear when the quadratic is ill-determined; coefficients in unscaled local coords"""
    I=np.arange(n*n)//n; J=np.arange(n*n)%n
    A=np.zeros((n*n,6,6)); b=np.zeros((n*n,6)); cnt=np.zeros(n*n)
    for di in range(-rad,rad+1):
        for dj in range(-rad,rad+1):
            i2=I+di; j2=J+dj; ok=(i2>=0)&(i2<n)&(j2>=0)&(j2<n)
            k=np.where(ok,i2*n+j2,0); m=ok&mask[k]
            phi=np.array([1,di,dj,di*di,di*dj,dj*dj],float)
            A+=m[:,None,None]*np.outer(phi,phi)[None]; b+=(m*val[k])[:,None]*phi[None]; cnt+=m
    near=np.zeros(n*n,bool)
    for di in (-1,0,1):
        for dj in (-1,0,1):
            i2=I+di; j2=J+dj; ok=(i2>=0)&(i2<n)&(j2>=0)&(j2<n); k=np.where(ok,i2*n+j2,0); near|=ok&mask[k]
    good=(cnt>=6)&near
    coef=np.zeros((n*n,6))
    idx=np.where(good)[0]
    if len(idx):
        w=np.linalg.eigvalsh(A[idx]); quad=w[:,0]>1e-9*w[:,-1]
        q=idx[quad]
        coef[q]=np.linalg.solve(A[q],b[q][:,:,None])[:,:,0]
        l=idx[~quad]
        A3=A[l][:,:3,:3]+1e-9*np.eye(3); coef[l,:3]=np.linalg.solve(A3,b[l][:,:3,None])[:,:,0]
    scale=np.array([1,1/h,1/h,1/h**2,1/h**2,1/h**2])
    return coef*scale,good
def rec_eval(coef,good,n,h,x,y,default):
    """Evaluate the reconstruction at points x,y (arrays): the cell's own quadratic; sqrt(max(0,.))"""
    i=np.clip(np.floor(x/h+n/2).astype(int),0,n-1); j=np.clip(np.floor(y/h+n/2).astype(int),0,n-1)
    c=i*n+j; u=x-((i+0.5)*h-n*h/2); v=y-((j+0.5)*h-n*h/2)
    q=coef[c]; val=q[:,0]+q[:,1]*u+q[:,2]*v+q[:,3]*u*u+q[:,4]*u*v+q[:,5]*v*v
    out=np.where(good[c],np.sqrt(np.maximum(val,0)),default[c])
    return out
class Rec:
    """The edge-aware reconstruction of one cycle's tractions (method 2 above)."""
    def __init__(self,tr,n,h,xc,yc):
        self.n,self.h=n,h; self.inc=[]
        for t in range(tr.shape[0]):
            p,q=tr[t,0],tr[t,1]
            rim=(p>0)&(p<0.3)
            s=np.sign((q*rim).sum()) or 1.0
            d=np.maximum(MU*p-s*q,0)
            pc,pg=local_quadratic_fits(p*p,p>0,n,h,xc,yc)
            # pressure fit used only where the cell or a neighbour is out of contact or p small (edge region); elsewhere p itself
            stick=d>1e-6*MU
            dc,dg=local_quadratic_fits(d*d,stick,n,h,xc,yc)
            self.inc.append((p,q,s,pc,pg,dc,dg,stick))
    def t(self,ti,x,y):
        p,q,s,pc,pg,dc,dg,stick=self.inc[ti]; n,h=self.n,self.h
        i=np.clip(np.floor(x/h+n/2).astype(int),0,n-1); j=np.clip(np.floor(y/h+n/2).astype(int),0,n-1); c=i*n+j
        pr=rec_eval(pc,pg,n,h,x,y,p)
        # outside: cells with no contact neighbourhood -> 0 (good False & p=0 default ok)
        dr=rec_eval(dc,dg,n,h,x,y,np.maximum(MU*p-s*q,0))
        # D only inside the stick region's neighbourhood; if the cell's fit has few stick cells -> d=0 (slip)
        dr=np.where(dg[c],dr,0.0)
        dr=np.minimum(dr,2*MU*pr)
        return pr, s*(MU*pr-dr)
def cell_averages(rec,tr,xc,yc,h,mf=8):
    """Cell averages (41, 3, cells) of the reconstruction, cells with r < 1.25 a."""
    n=rec.n; out=tr.copy()
    sel=np.where(np.hypot(xc,yc)<1.25)[0]
    offs=((np.arange(mf)+0.5)/mf-0.5)*h
    U,V=np.meshgrid(offs,offs,indexing='ij'); U=U.ravel(); V=V.ravel()
    X=(xc[sel][:,None]+U[None]).ravel(); Y=(yc[sel][:,None]+V[None]).ravel()
    for t in range(tr.shape[0]):
        p,q=rec.t(t,X,Y)
        out[t,0,sel]=p.reshape(len(sel),-1).mean(1); out[t,1,sel]=q.reshape(len(sel),-1).mean(1)
    return out
def evaluate(rec,avg,xc,yc,h,pts,L=7,M=None):
    """Surface paths (M, 41, 6) of the reconstruction at pts (method 2 above)."""
    M=M or 7*SUBCELLS
    n=rec.n; res=[]
    for (x,y) in pts:
        s0,s1,t0,t1=x-L*h/2,x+L*h/2,y-L*h/2,y+L*h/2
        # far field: every cell minus S, as rectangles
        x0=xc-h/2; x1=xc+h/2; y0=yc-h/2; y1=yc+h/2
        inter=(x1>s0)&(x0<s1)&(y1>t0)&(y0<t1)
        rects=[]  # (cx,cy,d1,d2,cellindex)
        far=np.where(~inter)[0]
        kp,kq=love(x,y,xc[far],yc[far],h/2,h/2)
        sig=np.einsum('kn,tn->tk',kp,avg[:,0,far])+np.einsum('kn,tn->tk',kq,avg[:,1,far])
        for c in np.where(inter)[0]:
            pieces=[]
            ax0,ax1,ay0,ay1=x0[c],x1[c],y0[c],y1[c]
            if ax0<s0: pieces.append((ax0,min(ax1,s0),ay0,ay1))
            if ax1>s1: pieces.append((max(ax0,s1),ax1,ay0,ay1))
            mx0,mx1=max(ax0,s0),min(ax1,s1)
            if mx1>mx0:
                if ay0<t0: pieces.append((mx0,mx1,ay0,min(ay1,t0)))
                if ay1>t1: pieces.append((mx0,mx1,max(ay0,t1),ay1))
            for (a0,a1,b0,b1) in pieces:
                kp,kq=love(x,y,np.array([(a0+a1)/2]),np.array([(b0+b1)/2]),(a1-a0)/2,(b1-b0)/2)
                sig+=np.outer(avg[:,0,c],kp[:,0])+np.outer(avg[:,1,c],kq[:,0])
        d=L*h/M; o=(np.arange(M)+0.5)*d-L*h/2
        U,V=np.meshgrid(o,o,indexing='ij'); X=x+U.ravel(); Y=y+V.ravel()
        kp,kq=love(x,y,X,Y,d/2,d/2)
        for t in range(avg.shape[0]):
            p,q=rec.t(t,X,Y)
            sig[t]+=kp@p+kq@q
        res.append(sig)
    return np.array(res)


def main_edges(directory, which):
    """Method 2 on the solver's tractions (`which` = "solver") or on the exact ones sampled at
    the cell centres ("exact"): the paths and Crossland's index at the fixture's fine points."""
    fx = json.loads((ROOT / "datasets" / "cattaneo_fatigue_surface.json").read_text())
    fp = [(x + 1e-9, y + 1e-9) for x, y in fx["fine"]["points"]]
    fref = np.array(fx["fine"]["stress"])
    for n in (32, 64, 128):
        meta = json.loads((pathlib.Path(directory) / f"tractions_{n}.json").read_text())
        p0 = meta["p0"]
        tr = np.fromfile(pathlib.Path(directory) / f"tractions_{n}.f64").reshape(41, 3, n * n) / p0
        h = 2 * meta["half"] / meta["a"]
        cell = np.arange(n * n)
        xc, yc = (cell // n + 0.5) * h - n * h / 2, (cell % n + 0.5) * h - n * h / 2
        if which == "exact":
            for t in range(41):
                tr[t, 0], tr[t, 1] = md_traction(xc, yc, t)
        rec = Rec(tr, n, h, xc, yc)
        got = evaluate(rec, cell_averages(rec, tr, xc, yc, h), xc, yc, h, fp)
        err = np.abs(got - fref).max(axis=(1, 2))
        c_got = np.array([crossland(got[m], p0) for m in range(len(fp))])
        c_ref = np.array([crossland(fref[m], p0) for m in range(len(fp))])
        print(f"{n}² edges ({which}, {SUBCELLS} subcells per cell): fine points max |Δσ|/p0 {err.max():.3e} "
              f"(median {np.median(err):.3e}), max |ΔCrossland| {np.abs(c_got - c_ref).max():.3f}, Crossland max "
              f"{c_got.max():.4f} at {np.round(fp[int(c_got.argmax())], 4).tolist()} (closed form {c_ref.max():.4f})",
              flush=True)


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    directory = args[0] if args else "/tmp"
    if "--edges" in sys.argv:
        SUBCELLS = int(args[1]) if len(args) > 1 else SUBCELLS
        main_edges(directory, "solver")
        main_edges(directory, "exact")
    else:
        main(directory)
