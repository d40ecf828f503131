"""Two halfspace binaries side by side on the frictionless Hertz case of verify/peers_3d.py
(R = 105 μm, E = 210 GPa, ν = 0.3, W = 80 mN, domain 4a, tol 1e-8), interleaved (A, B, A, B, …) so
that both see the same machine load: the fastest wall time and the least processor time of each
(docs/performance.md, issue 23), and how far B's pressure and approach are from A's.

Run: RAYON_NUM_THREADS=1 verify/.venv/bin/python verify/ab_3d.py OLD_BINARY NEW_BINARY 128,256,512,1024 5
(single-threaded on a loaded machine: the processor-time ratio is then the steady one).
"""
import json, subprocess, sys, os, tempfile, resource
import numpy as np
base, new = sys.argv[1], sys.argv[2]
sizes = [int(s) for s in sys.argv[3].split(",")]
reps = int(sys.argv[4]) if len(sys.argv) > 4 else 5
R,E,NU,W=105e-6,210e9,0.3,0.08
Es=E/(1-NU*NU); a=(3*W*R/(4*Es))**(1/3); L=4*a
def cmd(b,n,out=None):
    c=[b,"contact3d","--indenter",f"sphere:R={R}","--material",f"homogeneous:E={E},nu={NU}","--force",str(W),"--grid",str(n),"--extent",repr(L),"--tol","1e-8","--json"]
    return c+(["--out",out] if out else [])
for n in sizes:
    t={base:[],new:[]}; c={base:[],new:[]}
    for r in range(reps if n<=512 else max(2,reps//2)):
        for b in (base,new):
            r0=resource.getrusage(resource.RUSAGE_CHILDREN)
            d=json.loads(subprocess.run(cmd(b,n),check=True,capture_output=True,text=True).stdout)
            r1=resource.getrusage(resource.RUSAGE_CHILDREN)
            t[b].append(d["seconds"]); c[b].append(r1.ru_utime+r1.ru_stime-r0.ru_utime-r0.ru_stime)
    with tempfile.TemporaryDirectory() as tmp:
        outs=[]
        for b in (base,new):
            o=f"{tmp}/{os.path.basename(b)}.npz"
            d=json.loads(subprocess.run(cmd(b,n,o),check=True,capture_output=True,text=True).stdout)
            outs.append((np.load(o)["pressure"], d["depth"], d["iterations"]))
        p0,p1=outs[0][0],outs[1][0]
        dp=np.max(np.abs(p1-p0))/np.max(np.abs(p0)); dd=abs(outs[1][1]-outs[0][1])/abs(outs[0][1])
    mb,mn=min(t[base]),min(t[new])
    la=os.getloadavg()[0]
    cb,cn=min(c[base]),min(c[new])
    print(f"{n}: wall base {mb*1e3:.1f} ms new {mn*1e3:.1f} ms  base/new {mb/mn:.3f} | cpu(process) base {cb*1e3:.1f} new {cn*1e3:.1f} ratio {cb/cn:.3f}  it {outs[0][2]}->{outs[1][2]}  max|dp|/max p {dp:.2e} d(approach) {dd:.2e}  load {la:.1f}", flush=True)
