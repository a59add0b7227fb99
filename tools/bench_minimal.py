"""Reference point: a minimal fused SPH force loop, outside taisph, on this machine.

    python tools/bench_minimal.py field     # Taichi fields
    python tools/bench_minimal.py nd        # Taichi ndarrays (what taisph uses)

One parallel loop over 141 x 141 = 19,881 particles pre-sorted by cell in a periodic
unit box: cubic spline gradient, pressure and continuity sums, per-particle P/rho^2
read from an array (no EOS, no sort, no integration, no walls, no viscosity). It is
the floor taisph's force pass is compared with in docs/performance.md: timings on a
shared VM drift by up to 2x during a day, so the ratio measured in the same minute
says more than either number alone. Prints the best of 5 blocks of 100 calls.
"""
import math
import sys
import time

import numpy as np
import taichi as ti

mode = sys.argv[1] if len(sys.argv) > 1 else "nd"
ti.init(arch=ti.cpu, default_fp=ti.f64)
n_side=141; dx=1.0/n_side; h=1.3*dx; sup=2*h; G=int(1.0/sup); cell=1.0/G
N=n_side*n_side
pos0=np.stack(np.meshgrid((np.arange(n_side)+.5)*dx,(np.arange(n_side)+.5)*dx,indexing='ij'),-1).reshape(-1,2)
vec=ti.types.vector(2,ti.f64)
sigma=10/(7*math.pi)/h**2; gn=sigma/h**2
if mode=="field":
    X=ti.Vector.field(2,ti.f64,N); V=ti.Vector.field(2,ti.f64,N); R=ti.field(ti.f64,N); A=ti.Vector.field(2,ti.f64,N); D=ti.field(ti.f64,N)
    start=ti.field(ti.i32,G*G+1)
    X.from_numpy(pos0); R.fill(1000.)
    @ti.kernel
    def force():
        for i in range(N):
            xi=X[i]; ci=ti.cast(xi/cell,ti.i32)
            a=ti.Vector([0.,0.]); d=0.
            pi_=1000*20*20/7*((R[i]/1000)**7-1)/R[i]**2
            for oy in range(-1,2):
                for ox in range(-1,2):
                    cx=(ci[0]+ox)%G; cy=(ci[1]+oy)%G; c=cy*G+cx
                    for j in range(start[c],start[c+1]):
                        rij=xi-X[j]
                        rij-= ti.round(rij)
                        r2=rij.norm_sqr()
                        if r2<sup*sup and j!=i:
                            r=ti.sqrt(r2); q=r/h
                            g=0.
                            if q<1: g=-3+2.25*q
                            elif q<2: g=-0.75*(2-q)**2/q
                            grad=gn*g*rij
                            pj=R[j]
                            a-= 0.0001*(pi_+pj)*grad
                            d+=0.0001*(V[i]-V[j]).dot(grad)
            A[i]=a; D[i]=d
    # sort positions by cell once
    c=(np.floor(pos0[:,1]/cell).astype(int)%G)*G+(np.floor(pos0[:,0]/cell).astype(int)%G)
    order=np.argsort(c,kind='stable'); X.from_numpy(pos0[order])
    st=np.searchsorted(c[order],np.arange(G*G+1)); start.from_numpy(st.astype(np.int32))
    f=force
else:
    Xa=ti.ndarray(vec,N); Va=ti.ndarray(vec,N); Ra=ti.ndarray(ti.f64,N); Aa=ti.ndarray(vec,N); Da=ti.ndarray(ti.f64,N); sa=ti.ndarray(ti.i32,G*G+1)
    c=(np.floor(pos0[:,1]/cell).astype(int)%G)*G+(np.floor(pos0[:,0]/cell).astype(int)%G)
    order=np.argsort(c,kind='stable'); Xa.from_numpy(pos0[order]); Ra.fill(1000.)
    st=np.searchsorted(c[order],np.arange(G*G+1)); sa.from_numpy(st.astype(np.int32))
    @ti.kernel
    def forcen(X:ti.types.ndarray(vec,1),V:ti.types.ndarray(vec,1),R:ti.types.ndarray(ti.f64,1),A:ti.types.ndarray(vec,1),D:ti.types.ndarray(ti.f64,1),start:ti.types.ndarray(ti.i32,1)):
        for i in range(N):
            xi=X[i]; ci=ti.cast(xi/cell,ti.i32)
            a=ti.Vector([0.,0.]); d=0.
            pi_=1000*20*20/7*((R[i]/1000)**7-1)/R[i]**2
            for oy in range(-1,2):
                for ox in range(-1,2):
                    cx=(ci[0]+ox)%G; cy=(ci[1]+oy)%G; c=cy*G+cx
                    for j in range(start[c],start[c+1]):
                        rij=xi-X[j]
                        rij-= ti.round(rij)
                        r2=rij.norm_sqr()
                        if r2<sup*sup and j!=i:
                            r=ti.sqrt(r2); q=r/h
                            g=0.
                            if q<1: g=-3+2.25*q
                            elif q<2: g=-0.75*(2-q)**2/q
                            grad=gn*g*rij
                            pj=R[j]
                            a-= 0.0001*(pi_+pj)*grad
                            d+=0.0001*(V[i]-V[j]).dot(grad)
            A[i]=a; D[i]=d
    f=lambda: forcen(Xa,Va,Ra,Aa,Da,sa)
f(); ti.sync()
best=9
for _ in range(5):
    t=time.perf_counter()
    for _ in range(100): f()
    ti.sync(); best=min(best,(time.perf_counter()-t)/100)
print(mode, "%.3f ms  %.1f ns/particle"%(best*1e3,best/N*1e9))
