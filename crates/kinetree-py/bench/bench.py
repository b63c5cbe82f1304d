"""Per-call and batched timings of kinetree's Python bindings beside Pinocchio's (``pin``).

    python crates/kinetree-py/bench/bench.py [--pin-site /path/to/venv/lib/python3.X/site-packages]

For each robot (panda, ur5, talos_reduced) and call (FK of all links, a frame Jacobian, RNEA,
CRBA, ABA, the RNEA and ABA derivatives, one IK solve) it prints the time of one call from
Python, kinetree beside Pinocchio, and the time per state of kinetree's batched call beside
Pinocchio called in a Python loop (N = 10 000 states; 1 000 for the derivatives, whose three
nv x nv results per state would fill gigabytes), then the whole as a markdown table with the
machine load. Pinocchio is optional (``pip install pin``); ``--pin-site`` adds a virtualenv's
site-packages where it is installed. Every timing is the best of several repetitions, kinetree
and Pinocchio interleaved, so that machine load hits both alike. This is a benchmark, not a test.

The targets of issue #13: one call no slower than Pinocchio's (ratio ≤ 1), and a batched call at
least 20 times faster per state than Pinocchio in a loop.

Both sides are timed up to the numbers being in numpy arrays, as a Python user gets them.
Pinocchio's ``computeFrameJacobian``, ``rnea``, ``crba`` (full symmetric M), ``aba`` and the
derivative calls return new numpy arrays, as kinetree's do. Its FK (``framesForwardKinematics``: a
link's pose is a frame placement there; ``forwardKinematics`` alone places only the joints) writes
into its ``Data`` and returns nothing, so the "FK (all links)" row adds stacking the links' poses
into one ``(nlinks, 4, 4)`` array (``np.array([data.oMf[i].homogeneous for i in links])``), which
``link_placements`` returns. The row "FK (all links), into a buffer" is the other like-for-like
pair: kinetree's ``link_placements(q, buffer)`` beside ``framesForwardKinematics`` alone, both
writing into memory made once (Pinocchio's poses then stay in its ``Data``) and both given their
arguments positionally (as a keyword, ``out=buffer`` costs the abi3 build a dict: about 0.1 µs more).
Pinocchio's loops give each state its own ``v`` and ``a`` (or ``tau``), as the batched calls do.
kinetree's batched frame Jacobian, RNEA, CRBA, ABA and derivatives (and FK in the buffer row)
write into stacked arrays made once, as a sampling loop or a dataset writer reuses its buffers,
and as Pinocchio's loop reuses its ``Data``: a fresh ``(N, nv, nv)`` result would add the kernel's
zeroing of its pages on first touch (``--fresh`` times that variant instead).

The column "write floor" is what the batched results' bytes alone cost on this machine: numpy
filling arrays of the same shapes as the batched call's results (the same arrays when they are
buffers made once; new arrays each time with ``--fresh`` and in the "FK (all links)" row, which
returns new arrays), on one thread and on every core (``ndarray.fill`` releases the GIL), the
faster of the two, per state. No batched call can be faster than that; the column "bound" is
Pinocchio's loop divided by it, the largest speed-up the machine's memory allows. Where the
bound is below 20, so is the call, whatever its arithmetic (CRBA and the derivatives of a large
robot write ``nv x nv`` numbers per state: talos_reduced's 38 x 38 are 11.5 KB, 115 MB for
N = 10 000, far beyond the caches).

Pinocchio has no IK solver: its row is the closed-loop damped least-squares loop of Pinocchio's
documentation (``log6`` error, ``computeFrameJacobian``, ``integrate``) run to the same
tolerance.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import site
import threading
import time

import numpy as np

import kinetree

ROOT = pathlib.Path(__file__).resolve().parents[3]
URDF = ROOT / "tests" / "data" / "reference" / "urdf"
ROBOTS = {  # name: (urdf, floating, frame)
    "panda": ("panda.urdf", False, "panda_hand_tcp"),
    "ur5": ("ur5.urdf", False, "tool0"),
    "talos_reduced": ("talos_reduced.urdf", True, "gripper_left_base_link"),
}
N = 10_000
N_DERIVATIVES = 1_000


def best(fn, repeat=5, number=None):
    """Best time of one call of fn (s), over `repeat` runs of `number` calls."""
    if number is None:
        t0 = time.perf_counter()
        fn()
        one = max(time.perf_counter() - t0, 1e-7)
        number = max(1, min(20_000, int(0.05 / one)))
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        times.append((time.perf_counter() - t0) / number)
    return min(times)


def interleaved(fa, fb, rounds=3, **kw):
    ta, tb = [], []
    for _ in range(rounds):
        ta.append(best(fa, **kw))
        if fb is not None:
            tb.append(best(fb, **kw))
    return min(ta), (min(tb) if tb else None)


def write_floor(arrays, rounds=3):
    """Best time (s) to write the bytes of `arrays` (ndarrays, filled in place, or shapes, made
    new each time) with numpy, on one thread or split over every core, whichever is faster."""
    threads = os.cpu_count() or 1

    def fill(a, parts):
        if parts == 1:
            a.fill(0.0)
            return
        # ndarray.fill releases the GIL: the threads write their slices at once.
        chunks = np.array_split(np.arange(len(a)), parts)
        workers = [threading.Thread(target=a[c[0]:c[-1] + 1].fill, args=(0.0,)) for c in chunks if len(c)]
        for w in workers:
            w.start()
        for w in workers:
            w.join()

    def writer(parts):
        def run():
            for a in arrays:
                fill(np.empty(a) if isinstance(a, tuple) else a, parts)
        return run

    one, every = interleaved(writer(1), writer(threads) if threads > 1 else None,
                             rounds=rounds, repeat=3, number=1)
    return min(one, every) if every is not None else one


def pin_clik(pin, model, data, frame_id, goal, q0, tol=1e-6, iters=1000, damp=1e-12, dt=1.0):
    q = q0.copy()
    for _ in range(iters):
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacement(model, data, frame_id)
        err = pin.log6(data.oMf[frame_id].actInv(goal)).vector
        if np.linalg.norm(err) < tol:
            return q, True
        J = pin.computeFrameJacobian(model, data, q, frame_id, pin.ReferenceFrame.LOCAL)
        J = -np.dot(pin.Jlog6(data.oMf[frame_id].actInv(goal)), J)
        v = -J.T.dot(np.linalg.solve(J.dot(J.T) + damp * np.eye(6), err))
        q = pin.integrate(model, q, v * dt)
    return q, False


def fmt(t):
    if t is None:
        return "—"
    return f"{t * 1e6:.2f} µs" if t < 1e-3 else f"{t * 1e3:.2f} ms"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pin-site", help="site-packages of a virtualenv with pin installed")
    parser.add_argument("--robots", default=",".join(ROBOTS))
    parser.add_argument("--calls", default="",
                        help="comma-separated prefixes of the rows to run (\"FK,RNEA\"); all by default")
    parser.add_argument("--fresh", action="store_true",
                        help="batched calls return new arrays instead of writing into buffers made once")
    parser.add_argument("--rounds", type=int, default=3,
                        help="interleaved rounds per timing (more rounds: a steadier minimum on a busy machine)")
    args = parser.parse_args()
    if args.pin_site:
        site.addsitedir(args.pin_site)
    try:
        import pinocchio as pin
    except ImportError:
        pin = None
        print("pinocchio not found: kinetree timings only")

    load_before = os.getloadavg()[0]
    rows = []
    for robot in args.robots.split(","):
        urdf, floating, frame = ROBOTS[robot]
        m = kinetree.Model.from_urdf(str(URDF / urdf), floating=floating)
        rng = np.random.default_rng(0)
        q = m.random_configuration(seed=1)
        v, a = rng.uniform(-1, 1, m.nv), rng.uniform(-1, 1, m.nv)
        Q = m.random_configuration(N, seed=2)
        V, A = rng.uniform(-1, 1, (N, m.nv)), rng.uniform(-1, 1, (N, m.nv))
        nd = N_DERIVATIVES
        Qd, Vd, Ad = Q[:nd], V[:nd], A[:nd]
        if pin is not None:
            pm = (pin.buildModelFromUrdf(str(URDF / urdf), pin.JointModelFreeFlyer()) if floating
                  else pin.buildModelFromUrdf(str(URDF / urdf)))
            pd = pm.createData()
            fid = pm.getFrameId(frame)
            pq = pin.randomConfiguration(pm)
            pv, pa = rng.uniform(-1, 1, pm.nv), rng.uniform(-1, 1, pm.nv)
            PQ = [pin.randomConfiguration(pm) for _ in range(N)]
            PV = [rng.uniform(-1, 1, pm.nv) for _ in range(N)]
            PA = [rng.uniform(-1, 1, pm.nv) for _ in range(N)]
            PQd, PVd, PAd = PQ[:nd], PV[:nd], PA[:nd]
            lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
            links = [pm.getFrameId(name, pin.FrameType.BODY) for name in m.link_names]

            def pin_poses(x):
                pin.framesForwardKinematics(pm, pd, x)
                return np.array([pd.oMf[i].homogeneous for i in links])
        buffer = np.empty((len(m.link_names), 4, 4))
        buffers = np.empty((N, len(m.link_names), 4, 4))
        # Stacked outputs made once (None with --fresh: each batched call returns new arrays).
        nl, nv = len(m.link_names), m.nv
        jacobians, torques, masses = ((None, None, None) if args.fresh else
                                      (np.empty((N, 6, nv)), np.empty((N, nv)), np.empty((N, nv, nv))))
        parts = None if args.fresh else tuple(np.empty((nd, nv, nv)) for _ in range(3))
        # The arrays each batched call writes, for its write floor: the buffers themselves, or
        # the shapes of the new arrays it returns.
        written = {
            "FK (all links)": [(N, nl, 4, 4)],
            "FK (all links), into a buffer": [buffers],
            "frame Jacobian": [jacobians if jacobians is not None else (N, 6, nv)],
            "RNEA": [torques if torques is not None else (N, nv)],
            "CRBA": [masses if masses is not None else (N, nv, nv)],
            "ABA": [torques if torques is not None else (N, nv)],
            "RNEA derivatives": list(parts) if parts is not None else [(nd, nv, nv)] * 3,
            "ABA derivatives": list(parts) if parts is not None else [(nd, nv, nv)] * 3,
        }
        calls = {
            "FK (all links)": (lambda: m.link_placements(q), lambda: m.link_placements(Q),
                               (lambda: pin_poses(pq)) if pin else None,
                               (lambda: [pin_poses(x) for x in PQ]) if pin else None),
            "FK (all links), into a buffer": (
                lambda: m.link_placements(q, buffer), lambda: m.link_placements(Q, buffers),
                (lambda: pin.framesForwardKinematics(pm, pd, pq)) if pin else None,
                (lambda: [pin.framesForwardKinematics(pm, pd, x) for x in PQ]) if pin else None),
            "frame Jacobian": (lambda: m.frame_jacobian(q, frame), lambda: m.frame_jacobian(Q, frame, out=jacobians),
                               (lambda: pin.computeFrameJacobian(pm, pd, pq, fid, lwa)) if pin else None,
                               (lambda: [pin.computeFrameJacobian(pm, pd, x, fid, lwa) for x in PQ]) if pin else None),
            "RNEA": (lambda: m.rnea(q, v, a), lambda: m.rnea(Q, V, A, out=torques),
                     (lambda: pin.rnea(pm, pd, pq, pv, pa)) if pin else None,
                     (lambda: [pin.rnea(pm, pd, x, y, z) for x, y, z in zip(PQ, PV, PA)]) if pin else None),
            "CRBA": (lambda: m.crba(q), lambda: m.crba(Q, out=masses),
                     (lambda: pin.crba(pm, pd, pq)) if pin else None,
                     (lambda: [pin.crba(pm, pd, x) for x in PQ]) if pin else None),
            "ABA": (lambda: m.aba(q, v, a), lambda: m.aba(Q, V, A, out=torques),
                    (lambda: pin.aba(pm, pd, pq, pv, pa)) if pin else None,
                    (lambda: [pin.aba(pm, pd, x, y, z) for x, y, z in zip(PQ, PV, PA)]) if pin else None),
            "RNEA derivatives": (lambda: m.rnea_derivatives(q, v, a), lambda: m.rnea_derivatives(Qd, Vd, Ad, out=parts),
                                 (lambda: pin.computeRNEADerivatives(pm, pd, pq, pv, pa)) if pin else None,
                                 (lambda: [pin.computeRNEADerivatives(pm, pd, x, y, z) for x, y, z in zip(PQd, PVd, PAd)]) if pin else None),
            "ABA derivatives": (lambda: m.aba_derivatives(q, v, a), lambda: m.aba_derivatives(Qd, Vd, Ad, out=parts),
                                (lambda: pin.computeABADerivatives(pm, pd, pq, pv, pa)) if pin else None,
                                (lambda: [pin.computeABADerivatives(pm, pd, x, y, z) for x, y, z in zip(PQd, PVd, PAd)]) if pin else None),
        }
        wanted = [c.strip() for c in args.calls.split(",") if c.strip()]
        for name, (one, batch, pone, pbatch) in calls.items():
            if wanted and not any(name.startswith(w) for w in wanted):
                continue
            n = N_DERIVATIVES if "derivatives" in name else N
            t1, p1 = interleaved(one, pone, rounds=args.rounds)
            tb, pb = interleaved(batch, pbatch, rounds=args.rounds, repeat=3, number=1)
            floor = write_floor(written[name], rounds=args.rounds)
            rows.append((robot, name, t1, p1, tb / n, (pb / n) if pb else None, floor / n))
            print(rows[-1][0], rows[-1][1], fmt(t1), fmt(p1), fmt(tb / n), fmt(pb / n if pb else None),
                  "floor", fmt(floor / n), flush=True)

        if wanted and not any("IK".startswith(w) for w in wanted):
            continue
        # One IK solve of a reachable pose, from the neutral configuration.
        ik = kinetree.IkSolver(m, time_budget=None, seed=0)
        goals = m.frame_placement(m.random_configuration(50, seed=3), frame)
        ok = sum(ik.solve(frame, g)[1].converged for g in goals)
        t_ik = best(lambda: [ik.solve(frame, g) for g in goals], repeat=3, number=1) / len(goals)
        t_ikb = best(lambda: ik.solve_batch(frame, goals), repeat=3, number=1) / len(goals)
        p_ik = None
        if pin is not None:
            gq = [pin.randomConfiguration(pm) for _ in range(10)]
            pgoals = []
            for x in gq:
                pin.framesForwardKinematics(pm, pd, x)
                pgoals.append(pd.oMf[fid].copy())
            q0 = pin.neutral(pm)
            p_ik = best(lambda: [pin_clik(pin, pm, pd, fid, g, q0) for g in pgoals], repeat=2, number=1) / len(pgoals)
        rows.append((robot, f"IK solve ({ok}/{len(goals)} converged)", t_ik, p_ik, t_ikb, None, None))
        print(rows[-1][0], rows[-1][1], fmt(t_ik), fmt(p_ik), fmt(t_ikb), flush=True)

    print()
    print(f"Load average {load_before:.1f} before, {os.getloadavg()[0]:.1f} after; {os.cpu_count()} cores; "
          f"N = {N} ({N_DERIVATIVES} for the derivatives); times in µs per call or per state; "
          f"batched results {'in new arrays' if args.fresh else 'written into buffers made once'}.")
    print()
    print(markdown(rows, pin is not None))


def us(t):
    if t is None:
        return "—"
    t *= 1e6
    return f"{t:.3g}" if t < 100 else f"{t:.0f}"


def markdown(rows, with_pin):
    """The rows as a markdown table: one call beside Pinocchio (ratio ≤ 1 meets the target),
    batched per state beside Pinocchio in a Python loop (speed-up ≥ 20× meets the target), and
    the write floor of the batched results with the speed-up it bounds."""
    lines = [
        "| robot | call | kinetree, one call | Pinocchio, one call | ratio | "
        "kinetree batched, per state | Pinocchio loop, per state | speed-up | "
        "write floor, per state | bound |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for robot, name, t1, p1, tb, pb, floor in rows:
        ratio = f"{t1 / p1:.2f}" if with_pin and p1 else "—"
        up = f"{pb / tb:.1f}×" if with_pin and pb else "—"
        bound = f"{pb / floor:.0f}×" if with_pin and pb and floor else "—"
        lines.append(f"| {robot} | {name} | {us(t1)} | {us(p1)} | {ratio} | {us(tb)} | {us(pb)} | {up} "
                     f"| {us(floor)} | {bound} |")
    return "\n".join(lines)


if __name__ == "__main__":
    main()
