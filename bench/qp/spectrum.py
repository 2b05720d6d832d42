#!/usr/bin/python3
# bench/qp/spectrum.py — why the scaled instances are hard for MPRGP and easy for BLMVM.
# Statistically the same construction as bench/qp scaled_qp (tests/support/qp_problems.hpp),
# n = 1000, numpy's generator instead of std::mt19937_64: spectrum of F = D F0 D and of the
# Jacobi-scaled F.
import numpy as np
rng=np.random.default_rng(1)
n=1000
for kappa in [1e2,1e4,1e6]:
    F0=np.zeros((n,n)); deg=np.zeros(n)
    for i in range(n):
        for s in [1,2,7,31]:
            if i+s<n:
                w=0.1+rng.random(); F0[i,i+s]=F0[i+s,i]=-w; deg[i]+=w; deg[i+s]+=w
    shift=2*deg.max()/(10-1)
    F0+=np.diag(deg+shift)
    D=10**rng.uniform(0,0.5*np.log10(kappa/10),n)
    F=D[:,None]*F0*D[None,:]
    ev=np.linalg.eigvalsh(F)
    J=1/np.sqrt(np.diag(F)); FJ=J[:,None]*F*J[None,:]
    evj=np.linalg.eigvalsh(FJ)
    # fraction of eigenvalues per decade of the range
    dec=np.histogram(np.log10(ev/ev.max()),bins=np.arange(-7,0.01,1))[0]
    print(f"kappa<= {kappa:.0e}: kappa(F0)={np.linalg.cond(F0):.1f} kappa(F)={ev.max()/ev.min():.2e} kappa(Jacobi F)={evj.max()/evj.min():.2f}  eigenvalues per decade below lmax (1e-7..1): {dec.tolist()}")
