"""toppra and ruckig on the paths and limits that benches/timing.rs exports.

Usage: python3 benches/timing_peers.py PATHS.json RESULTS.json

Per motion, on the same certified waypoints and the same per-joint limits as cellc:
- `toppra_same` / `toppra_dense`: toppra's TOPP-RA (its default seidel solver, the
  first-order interpolation of the acceleration constraint, constant-acceleration steps)
  on cellc's own smoothed path, evaluated exactly (its lines and circular arcs, section by
  section, each from rest to rest), on a grid as dense as cellc's (`grid_step` of arc
  length and at most `max_turn` rad of an arc per step) and on one four times denser, the
  reference optimum on that path;
- `toppra_spline`: toppra as its examples use it, on a cubic spline through the waypoints
  (`SplineInterpolator` over `linspace(0, 1, m)`, toppra's own grid): a different path,
  which leaves the certified segments, so it says what toppra's usual use gives, not a
  like-for-like duration;
- `ruckig` / `ruckig_trapezoid`: Ruckig (the community version has no intermediate
  waypoints) from rest to rest on each straight segment, on the segment itself (one
  degree of freedom, the arc length, bound by every joint's limits), with the jerk
  limits as declared (none where the cell declares none) and with no jerk limit
  (acceleration-limited: the trapezoid, which cross-checks cellc's rest-to-rest
  baseline);
- `ruckig_joints`: Ruckig as it is usually called, every joint from rest to rest on each
  segment, phase-synchronised where it can be; where the joints' limits differ it falls
  back to time synchronisation and leaves the segment (shorter, not the same path).

Compute time: REPS timed repetitions of each motion's whole parameterisation (toppra:
constraints, grid, solve and output trajectory; ruckig: every segment's `calculate`), the
median in microseconds. A module that cannot be imported is reported as missing, and its
columns are left out.
"""

import json
import math
import statistics
import sys
import time

try:
    import numpy as np
except ImportError:  # pragma: no cover - reported to the Rust side
    np = None

try:
    import toppra as ta
    import toppra.algorithm as algo
    import toppra.constraint as constraint
    import toppra.interpolator as interpolator
except ImportError:
    ta = None

try:
    import ruckig
except ImportError:
    ruckig = None


def version(name):
    try:
        from importlib.metadata import version as v

        return v(name)
    except Exception:  # noqa: BLE001 - any failure means "unknown"
        return "?"


class Pieces(interpolator.AbstractGeometricPath if ta else object):
    """cellc's smoothed section: lines and circular arcs parameterised by arc length.

    At a junction of a line and an arc the arc's derivatives are taken (as timing.rs
    does): the curvature there bounds the speed.
    """

    def __init__(self, pieces, dof):
        self._dof = dof
        self.kinds, self.starts, self.lengths, self.data = [], [], [], []
        offset = 0.0
        for p in pieces:
            if "line" in p:
                a, b = np.array(p["line"]["a"]), np.array(p["line"]["b"])
                length = float(np.linalg.norm(b - a))
                self.kinds.append("line")
                self.data.append((a, (b - a) / length))
            else:
                arc = p["arc"]
                radius, angle = arc["radius"], arc["angle"]
                length = radius * angle
                self.kinds.append("arc")
                self.data.append(
                    (np.array(arc["centre"]), np.array(arc["u"]), np.array(arc["v"]), radius)
                )
            self.starts.append(offset)
            self.lengths.append(length)
            offset += length
        self.starts_np = np.array(self.starts)
        self.length = offset

    @property
    def dof(self):
        return self._dof

    @property
    def path_interval(self):
        return np.array([0.0, self.length])

    def pieces_at(self, ss):
        """The piece each of `ss` lies on (an arc's at a junction with a line)."""
        k = np.searchsorted(self.starts_np, ss, side="right") - 1
        k = np.clip(k, 0, len(self.kinds) - 1)
        for j in range(1, len(self.kinds)):
            if self.kinds[j] == "line" and self.kinds[j - 1] == "arc":
                k[(k == j) & (ss == self.starts[j])] = j - 1
        return k

    def __call__(self, path_positions, order=0):
        scalar = np.isscalar(path_positions)
        ss = np.atleast_1d(np.asarray(path_positions, dtype=float))
        k = self.pieces_at(ss)
        out = np.zeros((len(ss), self._dof))
        for j in np.unique(k):
            mask = k == j
            local = np.clip(ss[mask] - self.starts[j], 0.0, self.lengths[j])[:, None]
            if self.kinds[j] == "line":
                a, d = self.data[j]
                out[mask] = [a + d * local, d + 0.0 * local, 0.0 * local][order]
                continue
            centre, u, v, radius = self.data[j]
            theta = local / radius
            radial = u * np.cos(theta) + v * np.sin(theta)
            if order == 0:
                out[mask] = centre + radius * radial
            elif order == 1:
                out[mask] = -u * np.sin(theta) + v * np.cos(theta)
            else:
                out[mask] = -radial / radius
        return out[0] if scalar else out

    def grid(self, step, turn):
        """Each piece cut into equal steps of at most `step` (and `turn` rad of an arc)."""
        points = [0.0]
        for k, kind in enumerate(self.kinds):
            length = self.lengths[k]
            n = max(math.ceil(length / step), 1)
            if kind == "arc":
                n = max(n, math.ceil(length / self.data[k][3] / turn))
            points.extend(self.starts[k] + length * i / n for i in range(1, n + 1))
        points[-1] = self.length
        return np.array(points)


def limits(motion):
    v = np.array(motion["velocity"])
    a = np.array(motion["acceleration"])
    return np.stack([-v, v], axis=1), np.stack([-a, a], axis=1)


def toppra_duration(path, vlim, alim, gridpoints=None):
    """Duration of toppra's parameterisation of `path` from rest to rest."""
    constraints = [
        constraint.JointVelocityConstraint(vlim),
        constraint.JointAccelerationConstraint(alim),
    ]
    instance = algo.TOPPRA(
        constraints, path, gridpoints=gridpoints, parametrizer="ParametrizeConstAccel"
    )
    trajectory = instance.compute_trajectory(0, 0)
    if trajectory is None:
        raise RuntimeError("toppra found the path infeasible")
    return float(trajectory.duration)


def timed(reps, run):
    """(value of one run, median time in µs over `reps` timed runs)."""
    value = run()
    times = []
    for _ in range(reps):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return value, statistics.median(times) * 1e6


def toppra_same(motion, reps, density):
    vlim, alim = limits(motion)
    dof = motion["dim"]
    step, turn = motion["grid_step"] / density, motion["max_turn"] / density
    paths = [Pieces(section, dof) for section in motion["sections"]]
    grids = [p.grid(step, turn) for p in paths]

    def run():
        return sum(toppra_duration(p, vlim, alim, g) for p, g in zip(paths, grids))

    duration, us = timed(reps, run)
    return {"duration": duration, "median_us": us, "grid_points": sum(len(g) for g in grids)}


def toppra_spline(motion, reps):
    vlim, alim = limits(motion)
    waypoints = np.array(motion["waypoints"])
    ss = np.linspace(0.0, 1.0, len(waypoints))

    def run():
        path = interpolator.SplineInterpolator(ss, waypoints)
        return toppra_duration(path, vlim, alim)

    duration, us = timed(reps, run)
    return {"duration": duration, "median_us": us}


def ruckig_joints(motion, reps):
    """Ruckig's own use: every joint from rest to rest on each segment, phase-synchronised
    where Ruckig can (it falls back to time synchronisation, which leaves the segment,
    where the joints' limits do not allow one profile scaled for all)."""
    dof = motion["dim"]
    waypoints = motion["waypoints"]
    otg = ruckig.Ruckig(dof)
    trajectory = ruckig.Trajectory(dof)
    inputs = []
    for a, b in zip(waypoints, waypoints[1:]):
        inp = ruckig.InputParameter(dof)
        inp.current_position = a
        inp.target_position = b
        inp.max_velocity = motion["velocity"]
        inp.max_acceleration = motion["acceleration"]
        inp.max_jerk = [math.inf if j is None else j for j in motion["jerk"]]
        inp.synchronization = ruckig.Synchronization.Phase
        inputs.append(inp)

    def run():
        total = 0.0
        for inp in inputs:
            result = otg.calculate(inp, trajectory)
            if result not in (ruckig.Result.Working, ruckig.Result.Finished):
                raise RuntimeError(f"ruckig: {result}")
            total += trajectory.duration
        return total

    duration, us = timed(reps, run)
    return {"duration": duration, "median_us": us}


def ruckig_segments(motion, reps, jerk):
    """Ruckig on each straight segment itself: one degree of freedom, the arc length `s`
    from 0 to the segment's length, whose speed, acceleration and jerk are bound by the
    joint whose share of the segment is largest relative to its limit (so every joint
    stays within its own). With `jerk` false, no jerk limit: the trapezoid."""
    waypoints = motion["waypoints"]
    otg = ruckig.Ruckig(1)
    trajectory = ruckig.Trajectory(1)
    inputs = []
    for a, b in zip(waypoints, waypoints[1:]):
        length = math.dist(a, b)
        if length == 0.0:
            continue
        shares = [abs(y - x) / length for x, y in zip(a, b)]
        bound = lambda limits: min(  # noqa: E731 - a one-line minimum
            (l / c for l, c in zip(limits, shares) if c > 0.0 and l is not None),
            default=math.inf,
        )
        inp = ruckig.InputParameter(1)
        inp.current_position = [0.0]
        inp.target_position = [length]
        inp.max_velocity = [bound(motion["velocity"])]
        inp.max_acceleration = [bound(motion["acceleration"])]
        inp.max_jerk = [bound(motion["jerk"]) if jerk else math.inf]
        inputs.append(inp)

    def run():
        total = 0.0
        for inp in inputs:
            result = otg.calculate(inp, trajectory)
            if result not in (ruckig.Result.Working, ruckig.Result.Finished):
                raise RuntimeError(f"ruckig: {result}")
            total += trajectory.duration
        return total

    duration, us = timed(reps, run)
    return {"duration": duration, "median_us": us}


def main():
    with open(sys.argv[1]) as f:
        data = json.load(f)
    reps = data["reps"]
    missing = [
        name
        for name, module in (("numpy", np), ("toppra", ta), ("ruckig", ruckig))
        if module is None
    ]
    out = []
    for motion in data["motions"]:
        row = {}
        if np is not None and ta is not None:
            row["toppra_same"] = toppra_same(motion, reps, 1)
            row["toppra_dense"] = toppra_same(motion, max(reps // 4, 1), 4)
            row["toppra_spline"] = toppra_spline(motion, reps)
        if ruckig is not None:
            row["ruckig"] = ruckig_segments(motion, reps, True)
            row["ruckig_trapezoid"] = ruckig_segments(motion, reps, False)
            row["ruckig_joints"] = ruckig_joints(motion, reps)
        out.append(row)
    versions = {
        name: version(name) for name, module in (("toppra", ta), ("ruckig", ruckig)) if module
    }
    versions["python"] = sys.version.split()[0]
    with open(sys.argv[2], "w") as f:
        json.dump({"versions": versions, "missing": missing, "motions": out}, f)


if __name__ == "__main__":
    main()
