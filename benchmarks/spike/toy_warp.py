import time, sys, numpy as np, warp as wp
wp.config.quiet = True
N = 16

@wp.kernel
def batch(Y: wp.array2d(dtype=wp.float64), VY: wp.array2d(dtype=wp.float64), X: wp.array2d(dtype=wp.float64),
          VX: wp.array2d(dtype=wp.float64), k: wp.float64, c: wp.float64, m: wp.float64, dt: wp.float64,
          steps: int, FX: wp.array(dtype=wp.float64)):
    b = wp.tid()
    fx = FX[b]
    zero = wp.float64(0.0)
    for s in range(steps):
        for i in range(N):
            f = -k * Y[b, i] - c * VY[b, i] - wp.float64(1.0)
            if i > 0:
                f += k * (Y[b, i - 1] - Y[b, i])
            if i < N - 1:
                f += k * (Y[b, i + 1] - Y[b, i])
            VY[b, i] = VY[b, i] + f / m * dt
            VX[b, i] = VX[b, i] + fx / m * dt
        for it in range(10):
            for i in range(N):
                if Y[b, i] < wp.float64(-0.005):
                    jn = -VY[b, i] * m - wp.float64(0.1) * (Y[b, i] + wp.float64(0.005)) / dt * m
                    jn = wp.max(jn, zero)
                    VY[b, i] = VY[b, i] + jn / m
                    jt = -VX[b, i] * m
                    lim = wp.float64(0.5) * jn
                    jt = wp.clamp(jt, -lim, lim)
                    VX[b, i] = VX[b, i] + jt / m
        for i in range(N):
            Y[b, i] = Y[b, i] + VY[b, i] * dt
            X[b, i] = X[b, i] + VX[b, i] * dt

B, S = int(sys.argv[1]), int(sys.argv[2])
dev = sys.argv[3] if len(sys.argv) > 3 else "cpu"
rng = np.random.default_rng(0)
def args(B):
    return [wp.array(a, dtype=wp.float64, device=dev) for a in (rng.uniform(0, 1e-2, (B, N)), np.zeros((B, N)), np.zeros((B, N)), np.zeros((B, N)))]
f64 = wp.float64
t = time.perf_counter(); wp.init(); a = args(2)
wp.launch(batch, dim=2, inputs=[*a, f64(100.0), f64(1.0), f64(1.0), f64(1e-3), 10, wp.array(np.ones(2), dtype=wp.float64, device=dev)], device=dev); wp.synchronize(); tc = time.perf_counter() - t
a = args(B); fx = wp.array(np.linspace(0, 1, B), dtype=wp.float64, device=dev)
t = time.perf_counter()
wp.launch(batch, dim=B, inputs=[*a, f64(100.0), f64(1.0), f64(1.0), f64(1e-3), S, fx], device=dev); wp.synchronize(); tr = time.perf_counter() - t
print(f"warp {wp.__version__} device={dev} B={B} N={N} S={S}: init+compile {tc:.2f} s, run {tr:.3f} s, "
      f"{tr / (B * S) * 1e9:.1f} ns per scene-step, {tr / (B * S * N) * 1e9:.2f} ns per body-step; checksum {a[0].numpy().sum():.6e}")
