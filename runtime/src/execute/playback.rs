//! Playing a timed trajectory as a joint-trajectory controller does, and holding every
//! instant of it to the joints' limits.
//!
//! A controller given positions and velocities at each point (ros2_control's
//! `joint_trajectory_controller`, a UR's `servoj` stream) moves each joint between two
//! points along the cubic that meets both points' positions and velocities. The planner's
//! profile has a constant path acceleration between its knots, so on a straight part of
//! the path that cubic *is* the profile (a quadratic), and on an arc it stays within the
//! chord error of the arc. The cubic's speed is a quadratic in time, so its largest speed
//! and its turning positions on a step are found exactly, not by sampling at some rate
//! that could step over a peak. Accelerations are held to the limit without the cubic:
//! between two points, the least acceleration *any* motion needs to join them
//! ([`least_acceleration`]) must be within it. Points resampled at a control rate fall
//! anywhere in the profile, also across a switch from speeding up to braking, where a
//! cubic would overshoot what the profile does.
//!
//! What the points state is checked too: their velocities and accelerations are the
//! feed-forward a controller uses, so each must be within its limit, each stated
//! acceleration must agree with the motion it starts (a point that says "accelerating"
//! where the arm brakes is a fault), and where the cell declares a jerk limit the change
//! of the stated accelerations from point to point must keep to it.
//!
//! Why not the quintic through positions, velocities *and* accelerations (what that
//! controller does when given all three)? The profile's acceleration jumps at the knots
//! where it switches from speeding up to braking; a quintic forced to end a step with
//! the next step's acceleration overshoots in between by up to 75% of the jump's size
//! (its error on a unit step is `-A t³(1-t)²`, whose second derivative reaches `1.75 A`).
//! A controller fed at its own rate (`rate`) never interpolates across such a jump.

use crate::plan::TrajectoryPoint;

/// What a limit bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// A joint's position, between its lower and upper limits.
    Position,
    /// Speed.
    Velocity,
    /// Acceleration.
    Acceleration,
    /// Jerk, the change of acceleration.
    Jerk,
    /// How far a point's stated acceleration lies outside what the motion does on the
    /// steps either side of it.
    StatedAcceleration,
}

impl Quantity {
    /// The word for it in a message.
    pub fn word(self) -> &'static str {
        match self {
            Quantity::Position => "position",
            Quantity::Velocity => "speed",
            Quantity::Acceleration => "acceleration",
            Quantity::Jerk => "jerk",
            Quantity::StatedAcceleration => "stated acceleration",
        }
    }
}

/// One joint's limits, as the simulator holds a trajectory to them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct JointBounds {
    pub(crate) lower: f64,
    pub(crate) upper: f64,
    pub(crate) velocity: f64,
    pub(crate) acceleration: f64,
    pub(crate) jerk: Option<f64>,
}

/// How far over a limit the trajectory may go.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Slack {
    /// Joint units beyond a position limit.
    pub(crate) position: f64,
    /// Share of a speed, acceleration or jerk limit.
    pub(crate) rate: f64,
}

/// What is wrong with a trajectory as played.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Fault {
    /// Point `point` has the wrong number of values, a value that is not finite, or a
    /// time that does not come after the one before.
    Malformed { point: usize },
    /// A joint (index in the trajectory's columns) breaks a limit at `time`.
    Limit {
        joint: usize,
        quantity: Quantity,
        value: f64,
        limit: f64,
        time: f64,
    },
}

/// The cubic a controller follows between two points, for one joint.
struct Cubic {
    p0: f64,
    v0: f64,
    c2: f64,
    c3: f64,
}

impl Cubic {
    fn through(p0: f64, v0: f64, p1: f64, v1: f64, h: f64) -> Cubic {
        let slope = (p1 - p0) / h;
        Cubic {
            p0,
            v0,
            c2: (3.0 * slope - 2.0 * v0 - v1) / h,
            c3: (v0 + v1 - 2.0 * slope) / (h * h),
        }
    }
    fn position(&self, t: f64) -> f64 {
        self.p0 + t * (self.v0 + t * (self.c2 + t * self.c3))
    }
    fn velocity(&self, t: f64) -> f64 {
        self.v0 + t * (2.0 * self.c2 + 3.0 * self.c3 * t)
    }
    fn acceleration(&self, t: f64) -> f64 {
        2.0 * self.c2 + 6.0 * self.c3 * t
    }
    /// Times in `(0, h)` where the speed turns (the acceleration is zero).
    fn speed_turn(&self, h: f64) -> Option<f64> {
        let t = -self.c2 / (3.0 * self.c3);
        (t.is_finite() && t > 0.0 && t < h).then_some(t)
    }
    /// Times in `(0, h)` where the position turns (the velocity is zero).
    fn position_turns(&self, h: f64) -> [Option<f64>; 2] {
        let (a, b, c) = (3.0 * self.c3, 2.0 * self.c2, self.v0);
        let inside = |t: f64| (t.is_finite() && t > 0.0 && t < h).then_some(t);
        if a.abs() < 1e-300 {
            return [inside(-c / b), None];
        }
        let d = b * b - 4.0 * a * c;
        if d < 0.0 {
            return [None, None];
        }
        let r = d.sqrt();
        [inside((-b - r) / (2.0 * a)), inside((-b + r) / (2.0 * a))]
    }
}

/// The least bound on the acceleration of joint `j` under which some motion leaves `a`
/// and arrives at `b` in the time between them with their positions and velocities:
/// whatever a controller does between two points, it accelerates at least this much.
///
/// Measured from the trapezoid of the two speeds, a motion that speeds up at the bound
/// `A` for as long as it can and then slows down at `A` (or the reverse) covers the most
/// (the least) distance, `±(A h² − Δv²/A) / 4` beyond the trapezoid's `(v₀ + v₁) h / 2`;
/// solving for `A` gives the bound. A step of constant acceleration needs exactly that
/// acceleration, and a step that switches from speeding up to braking at `A` needs `A`:
/// no cubic's overshoot is charged to the trajectory.
fn least_acceleration(a: &TrajectoryPoint, b: &TrajectoryPoint, j: usize) -> f64 {
    let h = b.time - a.time;
    let dv = b.velocities[j] - a.velocities[j];
    let beyond = (b.positions[j] - a.positions[j]) - 0.5 * (a.velocities[j] + b.velocities[j]) * h;
    (2.0 * beyond.abs() + (4.0 * beyond * beyond + h * h * dv * dv).sqrt()) / (h * h)
}

/// Plays `points` against `joints` (one per column): the motion's duration, or the first
/// fault in time order.
pub(crate) fn play(
    points: &[TrajectoryPoint],
    joints: &[JointBounds],
    slack: Slack,
) -> Result<f64, Fault> {
    let n = joints.len();
    for (i, p) in points.iter().enumerate() {
        let finite = |v: &[f64]| v.len() == n && v.iter().all(|x| x.is_finite());
        let after = i == 0 || p.time > points[i - 1].time;
        if !(p.time.is_finite()
            && after
            && finite(&p.positions)
            && finite(&p.velocities)
            && finite(&p.accelerations))
        {
            return Err(Fault::Malformed { point: i });
        }
    }
    let over = |limit: f64| limit * (1.0 + slack.rate);
    let within = |joint: usize, quantity: Quantity, value: f64, limit: f64, time: f64| {
        if value.abs() > over(limit) {
            Err(Fault::Limit {
                joint,
                quantity,
                value,
                limit,
                time,
            })
        } else {
            Ok(())
        }
    };
    let position = |joint: usize, value: f64, bounds: &JointBounds, time: f64| {
        if value < bounds.lower - slack.position || value > bounds.upper + slack.position {
            let limit = if value < bounds.lower {
                bounds.lower
            } else {
                bounds.upper
            };
            Err(Fault::Limit {
                joint,
                quantity: Quantity::Position,
                value,
                limit,
                time,
            })
        } else {
            Ok(())
        }
    };
    // The range of each joint's played acceleration on the step that ends at the
    // current point (none before the first).
    let mut before: Vec<Option<(f64, f64)>> = vec![None; n];
    for (i, p) in points.iter().enumerate() {
        for (j, b) in joints.iter().enumerate() {
            position(j, p.positions[j], b, p.time)?;
            within(j, Quantity::Velocity, p.velocities[j], b.velocity, p.time)?;
            let a = p.accelerations[j];
            within(j, Quantity::Acceleration, a, b.acceleration, p.time)?;
            let after = points.get(i + 1).map(|next| {
                let h = next.time - p.time;
                let cubic = Cubic::through(
                    p.positions[j],
                    p.velocities[j],
                    next.positions[j],
                    next.velocities[j],
                    h,
                );
                (cubic, h, next)
            });
            let ends = after
                .as_ref()
                .map(|(c, h, _)| (c.acceleration(0.0), c.acceleration(*h)));
            // The stated acceleration is the one of the step that starts at the point
            // (the last point's, of the step that ends there), and a rate's samples fall
            // anywhere in a step: it must lie within what the motion does on the steps
            // either side.
            let range = [before[j], ends]
                .into_iter()
                .flatten()
                .map(|(x, y)| (x.min(y), x.max(y)))
                .reduce(|(lo, hi), (x, y)| (lo.min(x), hi.max(y)));
            if let Some((lo, hi)) = range {
                let off = if a < lo {
                    a - lo
                } else if a > hi {
                    a - hi
                } else {
                    0.0
                };
                if off.abs() > slack.rate * b.acceleration {
                    return Err(Fault::Limit {
                        joint: j,
                        quantity: Quantity::StatedAcceleration,
                        value: off,
                        limit: b.acceleration,
                        time: p.time,
                    });
                }
            }
            before[j] = ends;
            let Some((cubic, h, next)) = after else {
                continue;
            };
            if let Some(jerk) = b.jerk {
                let change = (next.accelerations[j] - a) / h;
                within(j, Quantity::Jerk, change, jerk, p.time)?;
            }
            // The least acceleration any motion between the two points needs.
            within(
                j,
                Quantity::Acceleration,
                least_acceleration(p, next, j),
                b.acceleration,
                p.time,
            )?;
            if let Some(t) = cubic.speed_turn(h) {
                within(
                    j,
                    Quantity::Velocity,
                    cubic.velocity(t),
                    b.velocity,
                    p.time + t,
                )?;
            }
            for t in cubic.position_turns(h).into_iter().flatten() {
                position(j, cubic.position(t), b, p.time + t)?;
            }
        }
    }
    Ok(points.last().map_or(0.0, |p| p.time - points[0].time))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SLACK: Slack = Slack {
        position: 1e-6,
        rate: 0.01,
    };

    fn joint() -> JointBounds {
        JointBounds {
            lower: -1.0,
            upper: 1.0,
            velocity: 1.0,
            acceleration: 2.0,
            jerk: None,
        }
    }

    fn point(time: f64, p: f64, v: f64, a: f64) -> TrajectoryPoint {
        TrajectoryPoint {
            time,
            positions: vec![p],
            velocities: vec![v],
            accelerations: vec![a],
        }
    }

    /// Rest to rest over 0.5 rad at 1 rad/s and 2 rad/s², played in `scale` of its time:
    /// 0.5 s speeding up to the speed limit, 0.5 s braking (a triangle).
    fn triangle(scale: f64) -> Vec<TrajectoryPoint> {
        let (a, t) = (2.0 / (scale * scale), 0.5 * scale);
        vec![
            point(0.0, 0.0, 0.0, a),
            point(t, 0.25, 1.0 / scale, -a),
            point(2.0 * t, 0.5, 0.0, -a),
        ]
    }

    #[test]
    fn a_profile_at_its_limits_plays_and_lasts_its_time() {
        let t = play(&triangle(1.0), &[joint()], SLACK).expect("within limits");
        assert!((t - 1.0).abs() < 1e-12, "{t}");
    }

    #[test]
    fn the_same_profile_played_faster_breaks_the_speed_limit_first() {
        let fault = play(&triangle(0.8), &[joint()], SLACK).expect_err("too fast");
        let Fault::Limit {
            quantity, value, ..
        } = fault
        else {
            panic!("{fault:?}");
        };
        // Played in 0.8 of the time, the profile accelerates at 2 / 0.8² = 3.125 rad/s²
        // from its first point on.
        assert_eq!(quantity, Quantity::Acceleration);
        assert!((value - 3.125).abs() < 1e-9, "{value}");
    }

    #[test]
    fn a_peak_between_points_is_found_although_no_point_carries_it() {
        // Both points at rest 0.2 rad apart over 0.2 s: the cubic's speed peaks at 1.5
        // rad/s mid-step, and its acceleration is 30 rad/s² at the ends.
        let points = [point(0.0, 0.0, 0.0, 30.0), point(0.2, 0.2, 0.0, -30.0)];
        let mut fast = joint();
        fast.acceleration = 30.0;
        match play(&points, &[fast], SLACK) {
            Err(Fault::Limit {
                joint: 0,
                quantity: Quantity::Velocity,
                value,
                time,
                ..
            }) => assert!((value - 1.5).abs() < 1e-9 && (time - 0.1).abs() < 1e-9),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_switch_from_speeding_up_to_braking_between_points_is_charged_what_it_needs() {
        // 0.5 rad from rest to rest in 1 s: speeding up at 2 rad/s² for half of it and
        // braking for the rest. The cubic through the two points accelerates at 3 rad/s²
        // at its ends; the motion needs 2.
        let points = [point(0.0, 0.0, 0.0, 2.0), point(1.0, 0.5, 0.0, -2.0)];
        assert!(play(&points, &[joint()], SLACK).is_ok());
        // Under a limit of 1.9 rad/s², points that state 1.9 are refused all the same.
        let mut weaker = joint();
        weaker.acceleration = 1.9;
        let stated = [point(0.0, 0.0, 0.0, 1.9), point(1.0, 0.5, 0.0, -1.9)];
        match play(&stated, &[weaker], SLACK) {
            Err(Fault::Limit {
                quantity: Quantity::Acceleration,
                value,
                ..
            }) => assert!((value - 2.0).abs() < 1e-9, "{value}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn an_overshoot_past_a_joint_limit_between_points_is_found() {
        // Leaves 0.95 rad at 1.2 rad/s toward the upper limit and comes back to it: the
        // motion turns at 1.01 rad, past the limit, although both points are within.
        let points = [point(0.0, 0.95, 1.2, -12.0), point(0.2, 0.95, -1.2, -12.0)];
        let mut loose = joint();
        loose.velocity = 2.0;
        loose.acceleration = 20.0;
        match play(&points, &[loose], SLACK) {
            Err(Fault::Limit {
                quantity: Quantity::Position,
                value,
                limit,
                ..
            }) => assert!(value > 1.0 && limit == 1.0, "{value}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_stated_acceleration_that_disagrees_with_the_motion_is_a_fault() {
        // The motion accelerates at 2 rad/s², the point says it brakes.
        let points = [point(0.0, 0.0, 0.0, -2.0), point(0.5, 0.25, 1.0, 0.0)];
        match play(&points, &[joint()], SLACK) {
            Err(Fault::Limit {
                quantity: Quantity::StatedAcceleration,
                value,
                ..
            }) => assert!((value + 4.0).abs() < 1e-9, "{value}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_declared_jerk_limit_bounds_the_change_of_stated_accelerations() {
        let mut jerky = joint();
        jerky.jerk = Some(5.0);
        // From +2 to -2 rad/s² in 0.5 s: 8 rad/s³.
        match play(&triangle(1.0), &[jerky], SLACK) {
            Err(Fault::Limit {
                quantity: Quantity::Jerk,
                value,
                ..
            }) => assert!((value + 8.0).abs() < 1e-9, "{value}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn malformed_points_are_faults_not_panics() {
        let mut short = triangle(1.0);
        short[1].velocities.clear();
        assert_eq!(
            play(&short, &[joint()], SLACK),
            Err(Fault::Malformed { point: 1 })
        );
        let mut back = triangle(1.0);
        back[2].time = back[1].time;
        assert_eq!(
            play(&back, &[joint()], SLACK),
            Err(Fault::Malformed { point: 2 })
        );
        let mut nan = triangle(1.0);
        nan[0].positions[0] = f64::NAN;
        assert_eq!(
            play(&nan, &[joint()], SLACK),
            Err(Fault::Malformed { point: 0 })
        );
        assert_eq!(play(&[], &[joint()], SLACK), Ok(0.0));
    }
}
