"""Instrumental-variable check of scripts/closed-loop.sh: one rate axis of the identification
flight, `ẋ = D_x x + D_u δ + D_0` (x the rate, δ the swept stick), fitted on the samples of
that axis' sweep by ordinary least squares and by two-stage least squares with the sweep's
commanded offset (before the pilot's correction; host-tests/sim/examples/sweep_excitation.rs)
and its lags as instruments. The recorded stick is sweep plus pilot, and the pilot reacts to
the states, noise and gusts included, so the stick is correlated with the equation error;
the commanded sweep is not. Pure Python (the lists are small, no numpy on the machine)."""
import csv

# Instrument lags (samples at 50 Hz): the rate answers the stick with a lag of 0.1 s (pitch,
# roll) to 1 s (yaw), so lagged sweeps correlate with the rate, the unlagged with the stick.
LAGS = [0, 5, 10, 25, 50]


def read_log(path):
    """Columns of a rotorid CSV log as lists of floats."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]} if rows else {}


def read_excitation(path):
    """{k: (channel, offset)} of the sweep schedule."""
    with open(path, newline="") as f:
        return {int(r["k"]): (r["channel"], float(r["offset"])) for r in csv.DictReader(f)}


def solve(a, b):
    """a x = b by Gaussian elimination with partial pivoting (a small and well posed)."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        if m[c][c] == 0:
            raise ValueError("singular normal equations")
        for r in range(c + 1, n):
            f = m[r][c] / m[c][c]
            for j in range(c, n + 1):
                m[r][j] -= f * m[c][j]
    x = [0.0] * n
    for r in reversed(range(n)):
        x[r] = (m[r][n] - sum(m[r][j] * x[j] for j in range(r + 1, n))) / m[r][r]
    return x


def gram(u, v):
    """Uᵀ V of two lists of rows."""
    return [[sum(a[i] * b[j] for a, b in zip(u, v)) for j in range(len(v[0]))]
            for i in range(len(u[0]))]


def fit_axis(log, excitation, channel, rate, stick):
    """(ordinary, instrumental) estimates [D_x, D_u, D_0] of `rate' = D_x rate + D_u stick +
    D_0` on the samples of `channel`'s sweep. The derivative is the central difference, the
    stick the mean of the two held over it (zero-order hold)."""
    t, x, u = log["time_s"], log[rate], log[stick]
    ks = [k for k in sorted(excitation) if excitation[k][0] == channel
          and 1 <= k < len(t) - 1 and k - max(LAGS) >= 0]
    y, reg, ins = [], [], []
    for k in ks:
        y.append((x[k + 1] - x[k - 1]) / (t[k + 1] - t[k - 1]))
        reg.append([x[k], 0.5 * (u[k - 1] + u[k]), 1.0])
        ins.append([excitation.get(k - lag, ("", 0.0))[1] for lag in LAGS] + [1.0])
    xtx, xty = gram(reg, reg), [row[0] for row in gram(reg, [[v] for v in y])]
    ordinary = solve(xtx, xty)
    # 2SLS: β = (XᵀZ (ZᵀZ)⁻¹ ZᵀX)⁻¹ XᵀZ (ZᵀZ)⁻¹ Zᵀy.
    ztz, ztx = gram(ins, ins), gram(ins, reg)
    zty = [row[0] for row in gram(ins, [[v] for v in y])]
    w = [solve(ztz, [ztx[i][j] for i in range(len(ins[0]))]) for j in range(len(reg[0]))]
    a = [[sum(w[i][m] * ztx[m][j] for m in range(len(ins[0]))) for j in range(len(reg[0]))]
         for i in range(len(reg[0]))]
    b = [sum(w[i][m] * zty[m] for m in range(len(ins[0]))) for i in range(len(reg[0]))]
    return ordinary, solve(a, b)
