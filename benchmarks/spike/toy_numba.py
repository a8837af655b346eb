"""Toy: B chains of N masses on springs/dampers, each pressed onto a rigid floor by a
unilateral contact (velocity-level impulse, clamped >= 0, with Coulomb friction on x),
stepped S steps with the whole time loop compiled."""
import time, sys, numpy as np, numba
from numba import njit, prange

@njit(cache=False, fastmath=False)
def one(y, vy, x, vx, k, c, m, dt, steps, fx):
    n = y.shape[0]
    for s in range(steps):
        for i in range(n):
            f = -k * y[i] - c * vy[i] - 1.0
            if i > 0: f += k * (y[i-1] - y[i])
            if i < n - 1: f += k * (y[i+1] - y[i])
            vy[i] += f / m * dt
            vx[i] += fx / m * dt
        for it in range(10):
            for i in range(n):
                if y[i] < -0.005:
                    jn = -vy[i] * m - 0.1 * (y[i] + 0.005) / dt * m
                    if jn < 0.0: jn = 0.0
                    vy[i] += jn / m
                    jt = -vx[i] * m
                    lim = 0.5 * jn
                    if jt > lim: jt = lim
                    if jt < -lim: jt = -lim
                    vx[i] += jt / m
        for i in range(n):
            y[i] += vy[i] * dt
            x[i] += vx[i] * dt

@njit(parallel=True)
def batch(Y, VY, X, VX, k, c, m, dt, steps, fx):
    for b in prange(Y.shape[0]):
        one(Y[b], VY[b], X[b], VX[b], k, c, m, dt, steps, fx[b])

B, N, S = int(sys.argv[1]), 16, int(sys.argv[2])
rng = np.random.default_rng(0)
args = lambda B: (rng.uniform(0, 1e-2, (B, N)), np.zeros((B, N)), np.zeros((B, N)), np.zeros((B, N)))
t = time.perf_counter(); batch(*args(2), 100.0, 1.0, 1.0, 1e-3, 10, np.ones(2)); tc = time.perf_counter() - t
a = args(B); t = time.perf_counter(); batch(*a, 100.0, 1.0, 1.0, 1e-3, S, np.linspace(0, 1, B)); tr = time.perf_counter() - t
print(f"numba {numba.__version__} threads={numba.get_num_threads()} B={B} N={N} S={S}: compile {tc:.2f} s, run {tr:.3f} s, "
      f"{tr / (B * S) * 1e9:.1f} ns per scene-step, {tr / (B * S * N) * 1e9:.2f} ns per body-step; checksum {a[0].sum():.6e}")
