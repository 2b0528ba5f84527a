"""A roller law by table, checked against the lamina loop: the numbers behind docs/PERFORMANCE.md,
"A roller law by table (study)". Not used by the simulator (yet).

    .venv/bin/python benches/roller_table/study.py        # about 2 s

A roller of n = 10 laminae without crowning (the GRC's bearings) loads lamina k with K·δ_k^(10/9),
δ_k = c + p·s_k. Its force, moment and tangent need five sums over the loaded laminae (E0, E1 of
δ^(10/9); S0, S1, S2 of δ^(1/9)), which are homogeneous in (c, p): a scale m^(10/9) or m^(1/9) times a
function of one variable u = m/(|p|·w) (m the most loaded lamina's approach, w a lamina's width). The
functions kink where a lamina unloads (u = 1 … n−1); `tables.KinkTable` puts knots there, evaluates the
last loaded lamina exactly (a second x^(1/9)) and tabulates the smooth rest per cell (Chebyshev, degree d).

Prints, for several table layouts, the worst error of each sum over 200 000 poses in physical units
(edge loading and poses within 1e-14 of every kink included) relative to the sum (E1, S1 relative to
E0·L/2, S0·L/2); then the check that a damped lamina law (q_k = K·δ_k^(1/9)·(δ_k + e·τ·(r_u + z_k·r_w)),
laminae with q_k <= 0 dropped) drops none exactly when its two extreme loaded laminae keep their load,
and the damped force and moment from the table against the loop's."""
import numpy as np, time, lawlib as LL, tables as T
t0=time.process_time()
N,B=LL.N,LL.B
def table_sums(tab,c,p,L):
    w=L/N; ap=np.abs(p); sg=np.where(p<0,-1.0,1.0)
    m=c+ap*(L/2-w/2)                     # most loaded lamina's approach
    out=np.zeros((5,c.size)); ld=m>0     # roller loaded iff m>0
    mm=m[ld]; v=ap[ld]*w/mm               # the one division
    cl,pl,Ll,ml=c[ld],p[ld],L[ld],mm
    def xphys(j,idx):                      # today's delta_j = c + p*s_j, j counted from the loaded end
        k=np.where(pl[idx]>=0, N-1-j, j)   # lamina index k in the roller
        s=-Ll[idx]/2+(k+0.5)*(Ll[idx]/N)      # same rounding as lawlib.exact_cp
        return (cl[idx]+pl[idx]*s)/ml[idx]
    F=tab(v,xphys)
    mb=mm**B; me=mb*mm                    # the scale's pow
    h=L/2
    out[:,ld]=[me*F[0], sg[ld]*me*h*F[1], mb*F[2], sg[ld]*mb*h*F[3], mb*h*h*F[4]]
    return out
rng=np.random.default_rng(1); n=200000
v=10**rng.uniform(-8,3,n); v[:2000]=0.0
J=rng.integers(1,10,20000); v[2000:22000]=1/(J*(1+10**rng.uniform(-15,-1,20000)*rng.choice([-1,1],20000)))
m=10**rng.uniform(-9,-3,n); L=rng.uniform(0.02,0.2,n); w=L/N
p=rng.choice([-1,1],n)*v*m/w; c=m-np.abs(p)*(L/2-w/2)
ex=LL.exact_cp(c,p,L)
for (U,s,nv,d) in [(16,0,1,5),(16,1,2,5),(16,1,2,7),(16,0,1,15)]:
    tab=T.KinkTable(U,s,nv,d,mode="exact")
    ap=table_sums(tab,c,p,L)
    e=np.array([np.abs(ap[0]-ex[0])/ex[0], np.abs(ap[1]-ex[1])/(ex[0]*L/2),
                np.abs(ap[2]-ex[2])/ex[2], np.abs(ap[3]-ex[3])/(ex[2]*L/2), np.abs(ap[4]-ex[4])/ex[4]]).max(1)
    print(f"physical-units sweep U={U} s={s} nv={nv} d={d} entries={tab.entries}: "+" ".join(f"{k}={x:.1e}" for k,x in zip(LL.NAMES,e)))

# ---- item 4: damping, q_k = K d^(1/9) (d + e tau (r_u + z_k r_w)), z_k = z_row + s_k
e9=10/9; K=1.0
tau=10**rng.uniform(-5,-2,n); ru=rng.normal(0,1,n)*m/1e-3*10**rng.uniform(-1,1,n)
rw=rng.normal(0,1,n)*np.abs(p)/1e-3*10**rng.uniform(-1,1,n)+rng.normal(0,1,n)*m/L/1e-3
zrow=rng.normal(0,0.05,n)
s=-L[:,None]/2+(np.arange(N)+0.5)*w[:,None]
d=c[:,None]+p[:,None]*s
g=d+e9*tau[:,None]*(ru[:,None]+(zrow[:,None]+s)*rw[:,None])
loaded=d>0; anyl=loaded.any(1)
all_ok=np.all(~loaded|(g>0),1)                       # exact: no loaded lamina dropped
kidx=np.arange(N)[None,:]
klo=np.where(loaded,kidx,N).min(1); khi=np.where(loaded,kidx,-1).max(1)
r=np.arange(n); two_ok=(g[r,np.clip(klo,0,N-1)]>0)&(g[r,np.clip(khi,0,N-1)]>0)
print(f"item4: loaded rollers {anyl.sum()}, all-kept {all_ok[anyl].sum()}, "
      f"mismatches two-end check vs full check: {(all_ok!=two_ok)[anyl].sum()}")
# loaded set is contiguous?
cont=(loaded.sum(1)==np.where(anyl,khi-klo+1,0)).all(); print("loaded set contiguous:",cont)
# damped force/moment from the table sums when check passes
tab=T.KinkTable(16,1,2,7,mode="exact"); S=table_sums(tab,c,p,L); ok=anyl&two_ok
A=e9*tau*(ru+zrow*rw); Bw=e9*tau*rw
Ft=K*(S[0]+A*S[2]+Bw*S[3]); Mt=K*(S[1]+A*S[3]+Bw*S[4])
q=np.where(loaded,K*np.where(loaded,d,0)**B*g,0.0)
Fx=q.sum(1); Mx=(q*s).sum(1)
scale=K*(ex[0]+np.abs(A)*ex[2]+np.abs(Bw)*np.abs(ex[3])+ np.abs(Bw)*ex[4]/(L/2))  # sum |terms|
print(f"damped law via table (d=7, 256): max|dF|/sum|terms| = {(np.abs(Ft-Fx)/scale)[ok].max():.1e}, "
      f"max|dM|/(sum|terms| L/2) = {(np.abs(Mt-Mx)/(scale*L/2))[ok].max():.1e}, "
      f"max|dF|/|F| = {(np.abs(Ft-Fx)/np.abs(Fx))[ok].max():.1e}")
print("cpu",time.process_time()-t0)
