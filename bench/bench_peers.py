#!/usr/bin/python3
"""grip beside its peers (issue #49): the same friction-constrained instances through grip
(its Python binding, and in C++ by the benchmarks' hook grip._grip_bench), QOCO,
Clarabel and ECOS (exact Coulomb cones), OSQP and proxsuite (friction pyramids), in one run.

The problem: min F2 = 1/2 sum_i w_i |x_i - s_i a_i|^2 over the contact forces x_i (3-vectors)
subject to G x + w_ext = 0 and a friction constraint per contact:

- exact cones (grip, QOCO, Clarabel, ECOS): (mu_i a_i.x_i, t1_i.x_i, t2_i.x_i) in the
  second-order cone Q^3, i.e. |x_i - (a_i.x_i) a_i| <= mu_i a_i.x_i, with t1_i, t2_i an
  orthonormal basis of the tangent plane. Clarabel and QOCO take the quadratic objective
  (P = W, q = -W t) directly. ECOS takes no quadratic objective: it gets the standard epigraph
  form min tau over (x, tau) with (tau, W^1/2 (x - t)) in Q^(3n+1), which minimises
  sqrt(2 F2) and so has the same minimiser.
- 4-facet pyramids (OSQP, proxsuite): |t1_i.x_i| <= mu_i/sqrt(2) a_i.x_i,
  |t2_i.x_i| <= mu_i/sqrt(2) a_i.x_i and a_i.x_i >= 0 (five linear rows per contact): the
  pyramid inscribed in the cone, a smaller feasible set than grip's, so some grasps that hold
  in the cones slip in the pyramids. proxsuite is its dense back end (proxqp.dense).

Instances: per n in (3, 5, 10, 20, 64), bench/bench_constrained.cpp's make_hard_instance drawn
with numpy's default_rng (seed 5000 + n): n hard fingers at uniform random points of a 4 cm
sphere, normals inward, mu uniform in [0.3, 1], squeeze 0.3 N, weights 1; a load of 0.5 to
200 N (log-uniform) in a random direction with moments 0.03 N m per N of it per component
before scaling; kept only when grip's fast path does not answer (the unconstrained optimum
leaves some cone). Grasps that slip (grip: Infeasible) stay in the set.

Timing: every solver's matrices are built, and its solver object set up (Clarabel's
DefaultSolver, QOCO.setup, OSQP.setup, proxsuite's QP.init), outside the timed region; only the
solve call is timed, by time.perf_counter, the least of three repeats per instance, each repeat
on a freshly set-up solver object (a cold solve: no warm start or adapted parameter carries
over). ECOS's Python API has no separate set-up: its ecos.solve call includes ECOS_setup.
grip's Python call is timed the same way (its Grasp built outside); its C++ mode is the least
of three solve_constrained calls timed by steady_clock inside the module. The solvers take turns
on each instance; Python's garbage collector is off while timing (collected between instances
every 500), and numpy/BLAS run on one thread.

Tolerances: every solver's defaults (grip 1e-12 relative equilibrium residual; Clarabel 1e-8;
QOCO 1e-7; ECOS 1e-8; proxsuite eps_abs 1e-5, eps_rel 0) except OSQP, whose defaults
(eps_abs = eps_rel = 1e-3) are not comparable with the others': the row "OSQP" is run at
proxsuite's defaults (eps_abs 1e-5, eps_rel 0); "OSQP (defaults)" is OSQP as shipped, for
reference. Output only is silenced (verbose off). OSQP has no warm start between repeats
(fresh set-up). Iteration limits are the defaults.

Run (the grip module built as in .ci/run's job_python, then):
    cmake -S . -B build/peers -DCMAKE_BUILD_TYPE=Release -DGRIP_BUILD_PYTHON=ON -DGRIP_BUILD_BENCH=ON \\
      -DGRIP_BUILD_EXAMPLES=OFF -DGRIP_BUILD_TESTS=OFF -DGRIP_BUILD_DOCS=OFF \\
      -DPython3_EXECUTABLE=/usr/bin/python3 -DCMAKE_CXX_FLAGS_RELEASE="-O3 -march=native -DNDEBUG"
    cmake --build build/peers -j2 --target grip_python grip_python_bench
    PYTHONPATH=build/peers/python /usr/bin/python3 bench/bench_peers.py [--quick] [--count N] [--out build/peers.md]
Run by /usr/bin/python3 it creates (or reuses) the venv build/peers-venv (python3 -m venv) with
numpy, scipy, qoco, clarabel, ecos, osqp and proxsuite from PyPI and runs itself again inside it;
build/peers-venv/bin/python bench/bench_peers.py runs it there directly. --quick: 2 000
instances per n (default 20 000).
"""

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse
import datetime
import gc
import platform
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VENV = os.path.join(ROOT, "build", "peers-venv")
PEER_PACKAGES = ["numpy", "scipy", "qoco", "clarabel", "ecos", "osqp", "proxsuite"]
SIZES = (3, 5, 10, 20, 64)


def ensure_venv():
    """Inside the venv: nothing. Otherwise create it (once), install the peers, run again in it."""
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        return
    python = os.path.join(VENV, "bin", "python")
    if not os.path.exists(python):
        subprocess.check_call([sys.executable, "-m", "venv", VENV])
        subprocess.check_call([python, "-m", "pip", "install", "-q", *PEER_PACKAGES])
    os.execv(python, [python, os.path.abspath(__file__), *sys.argv[1:]])


ensure_venv()

import numpy as np  # noqa: E402
import scipy  # noqa: E402
import scipy.sparse as sp  # noqa: E402

try:
    import grip  # noqa: E402
except ImportError:
    sys.path.insert(0, os.path.join(ROOT, "build", "peers", "python"))
    import grip  # noqa: E402
from grip import _grip_bench  # noqa: E402

import clarabel  # noqa: E402
import ecos  # noqa: E402
import osqp  # noqa: E402
import proxsuite  # noqa: E402
import qoco  # noqa: E402

REPEATS = 3
SQRT_HALF = np.sqrt(0.5)


def versions():
    from importlib.metadata import version

    out = {"python": platform.python_version()}
    for p in PEER_PACKAGES:
        out[p] = version(p)
    return out


# ---------------------------------------------------------------- instances


def make_hard_instance(rng, n):
    """bench_constrained.cpp's make_hard_instance<n>, drawn by numpy."""
    while True:
        theta = np.arccos(1 - 2 * rng.uniform(size=n))
        phi = 2 * np.pi * rng.uniform(size=n)
        mu = 0.3 + 0.7 * rng.uniform(size=n)
        u = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=1)
        size = 0.5 * 400.0 ** rng.uniform()
        w = rng.normal(size=6) * np.array([1, 1, 1, 0.03, 0.03, 0.03])
        w[:3] *= size / np.linalg.norm(w[:3])
        w[3:] *= size
        p, a = 0.04 * u, -u
        g = grip.Grasp(p, a, mu, squeeze=0.3)
        if not grip.solve_constrained(g, w).fast_path:
            return g, p, a, mu, w


def tangents(a):
    """(n, 3) t1 and t2: orthonormal bases of the tangent planes of the unit normals a."""
    e = np.zeros_like(a)
    e[np.arange(len(a)), np.argmin(np.abs(a), axis=1)] = 1
    t1 = np.cross(a, e)
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    return t1, np.cross(a, t1)


class Problem:
    """The matrices of one instance for every solver (built outside the timed region)."""

    def __init__(self, g, a, mu, w):
        n = len(mu)
        self.n, self.w = n, w
        self.G = g.grasp_matrix()  # (6, 3n)
        self.target = g.target().reshape(-1)  # s_i a_i
        self.wdiag = np.repeat(g.weights, 3)
        t1, t2 = tangents(a)
        self.a, self.mu = a, mu
        cone = np.zeros((3 * n, 3 * n))  # rows (mu a, t1, t2) per contact
        pyr = np.zeros((5 * n, 3 * n))  # rows t1 - c a, -t1 - c a, t2 - c a, -t2 - c a, -a
        for i in range(n):
            c = slice(3 * i, 3 * i + 3)
            cone[3 * i, c], cone[3 * i + 1, c], cone[3 * i + 2, c] = mu[i] * a[i], t1[i], t2[i]
            k = mu[i] * SQRT_HALF
            pyr[5 * i, c] = t1[i] - k * a[i]
            pyr[5 * i + 1, c] = -t1[i] - k * a[i]
            pyr[5 * i + 2, c] = t2[i] - k * a[i]
            pyr[5 * i + 3, c] = -t2[i] - k * a[i]
            pyr[5 * i + 4, c] = -a[i]
        self.cone, self.pyr = cone, pyr
        P = sp.diags(self.wdiag, format="csc")
        q = -self.wdiag * self.target
        # Clarabel: A x + s = b, s in {0}^6 x Q^3 x ... x Q^3.
        self.clarabel = (P, q, sp.csc_matrix(np.vstack([self.G, -cone])), np.concatenate([-w, np.zeros(3 * n)]),
                         [clarabel.ZeroConeT(6)] + [clarabel.SecondOrderConeT(3)] * n)
        # QOCO: A x = b, h - G x in Q^3 x ... x Q^3.
        self.qoco = dict(n=3 * n, m=3 * n, p=6, P=P, c=q, A=sp.csc_matrix(self.G), b=-w, G=sp.csc_matrix(-cone),
                         h=np.zeros(3 * n), l=0, nsoc=n, q=np.full(n, 3))
        # ECOS: over z = (x, tau), min tau; h - G z in Q^(3n+1) x Q^3 x ... x Q^3.
        sw = np.sqrt(self.wdiag)
        eg = np.zeros((6 * n + 1, 3 * n + 1))
        eg[0, 3 * n] = -1
        eg[1:3 * n + 1, :3 * n] = -np.diag(sw)
        eg[3 * n + 1:, :3 * n] = -cone
        self.ecos = dict(c=np.concatenate([np.zeros(3 * n), [1.0]]), G=sp.csc_matrix(eg),
                         h=np.concatenate([[0.0], -sw * self.target, np.zeros(3 * n)]),
                         dims={"l": 0, "q": [3 * n + 1] + [3] * n, "e": 0},
                         A=sp.csc_matrix(np.hstack([self.G, np.zeros((6, 1))])), b=-w)
        # OSQP: l <= A x <= u, equality rows first.
        inf = np.full(5 * n, -np.inf)
        self.osqp = dict(P=sp.triu(P, format="csc"), q=q, A=sp.csc_matrix(np.vstack([self.G, pyr])),
                         l=np.concatenate([-w, inf]), u=np.concatenate([-w, np.zeros(5 * n)]))
        # proxsuite (dense): A x = b, l <= C x <= u.
        self.prox = (np.diag(self.wdiag), q, self.G, -w, pyr, inf, np.zeros(5 * n))
        # The pyramids' reference status (untimed): Clarabel on the pyramid problem.
        self.pyramid_ref = (P, q, sp.csc_matrix(np.vstack([self.G, pyr])), np.concatenate([-w, np.zeros(5 * n)]),
                            [clarabel.ZeroConeT(6), clarabel.NonnegativeConeT(5 * n)])

    def residual(self, x):
        """|G x + w_ext| / |w_ext|."""
        return float(np.linalg.norm(self.G @ x[:3 * self.n] + self.w) / np.linalg.norm(self.w))

    def objective(self, x):
        d = x[:3 * self.n] - self.target
        return 0.5 * float(self.wdiag @ (d * d))


# ---------------------------------------------------------------- solvers
# Each returns (seconds, status class, raw status, iterations, x or None): the least of REPEATS
# timed solve calls, each on a freshly set-up solver.


def least(setup, solve):
    best, out = np.inf, None
    for _ in range(REPEATS):
        obj = setup()
        t0 = time.perf_counter()
        r = solve(obj)
        t = time.perf_counter() - t0
        if t < best:
            best = t
        out = r
    return best, out


def run_grip_py(pr, g):
    t, s = least(lambda: None, lambda _: grip.solve_constrained(g, pr.w))
    cls = {grip.Status.Ok: "solved", grip.Status.Infeasible: "infeasible"}.get(s.status, "other")
    return t, cls, s.status.name, s.iterations, s.forces.reshape(-1) if cls == "solved" else None


def run_grip_cpp(pr, g):
    t, status, iterations, pr.grip_passes = _grip_bench.time_constrained(g, pr.w, REPEATS)
    cls = {grip.Status.Ok: "solved", grip.Status.Infeasible: "infeasible"}.get(status, "other")
    return t, cls, status.name, iterations, None


CLARABEL_CLASS = {"Solved": "solved", "AlmostSolved": "solved", "PrimalInfeasible": "infeasible",
                  "AlmostPrimalInfeasible": "infeasible"}


def run_clarabel(pr, g):
    P, q, A, b, cones = pr.clarabel

    def setup():
        s = clarabel.DefaultSettings()
        s.verbose = False
        return clarabel.DefaultSolver(P, q, A, b, cones, s)

    t, sol = least(setup, lambda solver: solver.solve())
    raw = str(sol.status).split(".")[-1]
    cls = CLARABEL_CLASS.get(raw, "other")
    return t, cls, raw, sol.iterations, np.array(sol.x) if cls == "solved" else None


def run_qoco(pr, g):
    def setup():
        prob = qoco.QOCO()
        prob.setup(**pr.qoco, verbose=0)
        return prob

    t, res = least(setup, lambda prob: prob.solve())
    cls = "solved" if res.status in ("QOCO_SOLVED", "QOCO_SOLVED_INACCURATE") else "other"
    return t, cls, res.status, res.iters, np.array(res.x) if cls == "solved" else None


def run_ecos(pr, g):
    e = pr.ecos
    t, res = least(lambda: None, lambda _: ecos.solve(e["c"], e["G"], e["h"], e["dims"], e["A"], e["b"], verbose=False))
    flag = res["info"]["exitFlag"]
    cls = {0: "solved", 10: "solved", 1: "infeasible", 11: "infeasible"}.get(flag, "other")
    return t, cls, res["info"]["infostring"], res["info"]["iter"], res["x"] if cls == "solved" else None


OSQP_CLASS = {"solved": "solved", "solved inaccurate": "solved", "primal infeasible": "infeasible",
              "primal infeasible inaccurate": "infeasible"}


def osqp_runner(settings):
    def run(pr, g):
        def setup():
            prob = osqp.OSQP()
            prob.setup(**pr.osqp, verbose=False, **settings)
            return prob

        t, res = least(setup, lambda prob: prob.solve(raise_error=False))
        raw = res.info.status
        cls = OSQP_CLASS.get(raw, "other")
        return t, cls, raw, res.info.iter, np.array(res.x) if cls == "solved" else None

    return run


def run_proxsuite(pr, g):
    H, q, A, b, C, lo, up = pr.prox
    n = len(q)

    def setup():
        qp = proxsuite.proxqp.dense.QP(n, A.shape[0], C.shape[0])
        qp.settings.verbose = False
        qp.init(H, q, A, b, C, lo, up)
        return qp

    def solve(qp):
        qp.solve()
        return qp

    t, qp = least(setup, solve)
    st = qp.results.info.status
    raw = str(st).split(".")[-1]
    cls = {"PROXQP_SOLVED": "solved", "PROXQP_PRIMAL_INFEASIBLE": "infeasible"}.get(raw, "other")
    return t, cls, raw, qp.results.info.iter, np.array(qp.results.x) if cls == "solved" else None


def pyramid_reference(pr):
    """Clarabel's status class on the pyramid problem (not timed): the reference of OSQP and proxsuite."""
    s = clarabel.DefaultSettings()
    s.verbose = False
    sol = clarabel.DefaultSolver(*pr.pyramid_ref, s).solve()
    return CLARABEL_CLASS.get(str(sol.status).split(".")[-1], "other")


# (name, cone, runner)
SOLVERS = [
    ("grip (C++)", "cone", run_grip_cpp),
    ("grip (Python)", "cone", run_grip_py),
    ("Clarabel", "cone", run_clarabel),
    ("QOCO", "cone", run_qoco),
    ("ECOS", "cone", run_ecos),
    ("proxsuite", "pyramid", run_proxsuite),
    ("OSQP", "pyramid", osqp_runner(dict(eps_abs=1e-5, eps_rel=0.0))),
    ("OSQP (defaults)", "pyramid", osqp_runner({})),
]


# ---------------------------------------------------------------- the run


def run_size(n, count, seed):
    rng = np.random.default_rng(seed)
    k = len(SOLVERS)
    times = np.zeros((k, count))
    iters = np.zeros((k, count), dtype=np.int64)
    cls = np.empty((k, count), dtype=object)
    pyr_ref = np.empty(count, dtype=object)
    passes = np.zeros(count, dtype=np.int64)
    raw = [dict() for _ in SOLVERS]
    resid = [[] for _ in SOLVERS]
    objgap = [[] for _ in SOLVERS]
    gc.collect()
    gc.disable()
    try:
        for j in range(count):
            g, p, a, mu, w = make_hard_instance(rng, n)
            pr = Problem(g, a, mu, w)
            pyr_ref[j] = pyramid_reference(pr)
            f_grip = None
            for s, (name, cone, run) in enumerate(SOLVERS):
                t, c, r, it, x = run(pr, g)
                times[s, j], cls[s, j], iters[s, j] = t, c, it
                raw[s][r] = raw[s].get(r, 0) + 1
                if x is not None:
                    resid[s].append(pr.residual(x))
                    f = pr.objective(x)
                    if name == "grip (Python)":
                        f_grip = f
                    elif cone == "cone" and f_grip is not None:
                        objgap[s].append((f - f_grip) / f_grip)
            passes[j] = pr.grip_passes
            if j % 500 == 499:
                gc.enable()
                gc.collect()
                gc.disable()
    finally:
        gc.enable()
    return dict(times=times, iters=iters, cls=cls, raw=raw, resid=resid, objgap=objgap, pyr_ref=pyr_ref, passes=passes)


def us(x):
    return f"{x * 1e6:,.1f}" if x < 1e-4 else f"{x * 1e6:,.0f}"


def ratio(x):
    return f"{x:.1f}" if x < 100 else f"{x:.0f}"


def pct(x):
    return f"{100 * x:.2f}"


def report(results, count, vers, elapsed):
    lines = []
    out = lines.append
    gi = [s for s, (name, _, _) in enumerate(SOLVERS) if name == "grip (Python)"][0]
    out(f"{count:,} instances per n. Times in µs, the least of {REPEATS} per instance. Solved / infeasible / other: "
        "% of the instances. Agrees: % whose status (solved or infeasible) is grip's; for the pyramid solvers "
        "also the pyramid problem's own reference (Clarabel on the pyramids, untimed). Ratio: the peer's figure "
        "over grip's through Python (the goal: ≥ 10); on the grip (C++) rows, in brackets, grip Python's over "
        "grip C++'s.")
    out("")
    out("| n | solver | friction | median | p99.99 | max | median it. | max it. | solved | infeasible | other | "
        "agrees with grip | agrees, pyramid ref. | ratio median | ratio p99.99 |")
    out("| ---: | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    summary = []
    for n, r in results.items():
        times, iters, cls = r["times"], r["iters"], r["cls"]
        gmed, gp = np.median(times[gi]), np.quantile(times[gi], 0.9999)
        worst = {"cone": [np.inf, np.inf], "pyramid": [np.inf, np.inf]}
        for s, (name, cone, _) in enumerate(SOLVERS):
            t = times[s]
            med, p, mx = np.median(t), np.quantile(t, 0.9999), t.max()
            frac = {c: np.mean(cls[s] == c) for c in ("solved", "infeasible", "other")}
            agree = pct(np.mean(cls[s] == cls[gi]))
            agree_ref = pct(np.mean(cls[s] == r["pyr_ref"])) if cone == "pyramid" else "—"
            if name == "grip (Python)":
                rm = rp = "—"
            elif name.startswith("grip"):
                rm, rp = f"({ratio(gmed / med)})", f"({ratio(gp / p)})"
            else:
                rm, rp = ratio(med / gmed), ratio(p / gp)
                worst[cone][0] = min(worst[cone][0], med / gmed)
                worst[cone][1] = min(worst[cone][1], p / gp)
            out(f"| {n} | {name} | {cone} | {us(med)} | {us(p)} | {us(mx)} | {np.median(iters[s]):.0f} | "
                f"{iters[s].max()} | {pct(frac['solved'])} | {pct(frac['infeasible'])} | {pct(frac['other'])} | "
                f"{agree} | {agree_ref} | {rm} | {rp} |")
        summary.append((n, np.mean(cls[gi] == "infeasible"), np.mean(r["pyr_ref"] == "infeasible"), worst))
    out("")
    out("| n | slip: cones (grip) | slip: pyramids (ref.) | least ratio, exact-cone peers: median / p99.99 | "
        "least ratio, pyramid peers: median / p99.99 | ≥ 10 against every exact-cone peer | ≥ 10 against every peer |")
    out("| ---: | ---: | ---: | ---: | ---: | --- | --- |")
    for n, slip, slip_pyr, worst in summary:
        c, py = worst["cone"], worst["pyramid"]
        ok_c = "yes" if min(c) >= 10 else "no"
        ok_all = "yes" if min(c + py) >= 10 else "no"
        out(f"| {n} | {pct(slip)} % | {pct(slip_pyr)} % | {ratio(c[0])} / {ratio(c[1])} | {ratio(py[0])} / {ratio(py[1])} "
            f"| {ok_c} | {ok_all} |")
    out("")
    out("grip's iterations are its interior-point iterations (0: answered by Newton's passes alone); its O(n) "
        "passes, median / max: " + "; ".join(f"n = {n}: {np.median(r['passes']):.0f} / {r['passes'].max()}"
                                            for n, r in results.items()) + ".")
    out("")
    out("Accuracy on the instances each solver calls solved: |G x + w_ext| / |w_ext| (median, max) and, for the "
        "exact-cone peers, (F2 - F2_grip) / F2_grip where grip also solved (median, min, max; below 0: under "
        "grip's optimum, by leaving the cones or the equilibrium within the solver's tolerance).")
    out("")
    out("| n | solver | residual: median | max | objective vs grip: median | min | max |")
    out("| ---: | --- | ---: | ---: | ---: | ---: | ---: |")
    for n, r in results.items():
        for s, (name, cone, _) in enumerate(SOLVERS):
            res, og = r["resid"][s], r["objgap"][s]
            a = ("—", "—") if not res else (f"{np.median(res):.1e}", f"{np.max(res):.1e}")
            b = ("—",) * 3 if not og else (f"{np.median(og):.1e}", f"{np.min(og):.1e}", f"{np.max(og):.1e}")
            out(f"| {n} | {name} | {a[0]} | {a[1]} | {b[0]} | {b[1]} | {b[2]} |")
    out("")
    out("The solvers' own statuses (count):")
    out("")
    out("| n | solver | statuses |")
    out("| ---: | --- | --- |")
    for n, r in results.items():
        for s, (name, _, _) in enumerate(SOLVERS):
            st = ", ".join(f"{k} {v}" for k, v in sorted(r["raw"][s].items(), key=lambda kv: -kv[1]))
            out(f"| {n} | {name} | {st} |")
        st = ", ".join(f"{k} {v}" for k, v in sorted(zip(*np.unique(r["pyr_ref"].astype(str), return_counts=True)),
                                                     key=lambda kv: -kv[1]))
        out(f"| {n} | pyramid ref. (Clarabel, untimed) | {st} |")
    out("")
    out("Versions: " + ", ".join(f"{k} {v}" for k, v in vers.items()) + f". Run time {elapsed / 60:.1f} min.")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--count", type=int, default=20000, help="instances per n (default 20 000)")
    ap.add_argument("--quick", action="store_true", help="2 000 instances per n")
    ap.add_argument("--sizes", type=int, nargs="*", default=list(SIZES))
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "peers.md"))
    args = ap.parse_args()
    count = 2000 if args.quick else args.count
    vers = versions()
    model = platform.processor() or platform.machine()
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name:"):
                model = line.split(":", 1)[1].strip()
    except OSError:
        pass
    print(f"machine: {model}, {os.cpu_count()} cores; {datetime.date.today()}", flush=True)
    print("versions: " + ", ".join(f"{k} {v}" for k, v in vers.items()), flush=True)
    t0 = time.time()
    results = {}
    for n in args.sizes:
        s = time.time()
        results[n] = run_size(n, count, 5000 + n)
        print(f"n = {n}: {count} instances in {time.time() - s:.0f} s", flush=True)
    text = report(results, count, vers, time.time() - t0)
    print()
    print(text)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as f:
        f.write(text + "\n")


if __name__ == "__main__":
    main()
