//! The queue of canonical calls held back while cutter compensation
//! waits to see the next move: the end point of a compensated move is
//! only known once the following move shows the corner's shape, so the
//! move (and every call made after it) waits here.

use crate::canon::{Arc, Canon, Plane, Pose};
use crate::error::{InterpError, Result};
use crate::find::find_turn;

/// A held-back canonical call.
#[derive(Debug, Clone, PartialEq)]
pub enum Queued {
    /// A straight move; `dir` is the programmed direction (in the comp
    /// plane's first/second axes) used to detect a reversed clip.
    Straight {
        feed: bool,
        line: i32,
        dir: (f64, f64),
        end: Pose,
    },
    /// An arc in the comp plane; positions are (first, second) of the
    /// plane (Z, X in G18).
    ArcFeed {
        line: i32,
        original_turns: f64,
        end1: f64,
        end2: f64,
        center1: f64,
        center2: f64,
        turn: i32,
        end3: f64,
        rest: Pose,
    },
    SetFeedRate(f64),
    Dwell(f64),
    /// Feed mode (0 per minute, 1 per revolution) of a spindle.
    SetFeedMode(i32, i32),
    MistOn,
    MistOff,
    FloodOn,
    FloodOff,
    /// The spindle calls, with the spindle's number.
    SpindleClockwise(i32),
    SpindleCounterClockwise(i32),
    SpindleStop(i32),
    SetSpindleMode(i32, f64),
    SetSpindleSpeed(i32, f64),
    Comment(String),
}

/// The held-back calls and the start point of the first held move.
#[derive(Debug, Clone, Default)]
pub struct CompQueue {
    pub(crate) items: Vec<Queued>,
    endpoint: (f64, f64),
    endpoint_valid: bool,
}

/// Lathe tools: where the tool's origin is relative to the centre of
/// its nose radius (orientations 1-8, in the XZ plane).
fn lathe_x(plane: Plane, orientation: i32, radius: f64, x: f64) -> f64 {
    if plane != Plane::Xz {
        return x;
    }
    match orientation {
        1 | 2 | 6 => x - radius,
        3 | 4 | 8 => x + radius,
        _ => x,
    }
}

fn lathe_z(plane: Plane, orientation: i32, radius: f64, z: f64) -> f64 {
    if plane != Plane::Xz {
        return z;
    }
    match orientation {
        2 | 3 | 7 => z - radius,
        1 | 4 | 5 => z + radius,
        _ => z,
    }
}

/// The plane and tool geometry dequeuing needs.
#[derive(Debug, Clone, Copy)]
pub struct CompGeometry {
    /// The comp plane (XY or XZ).
    pub plane: Plane,
    /// Lathe tool orientation (0 or 9 for a mill tool).
    pub orientation: i32,
    /// The compensation radius.
    pub radius: f64,
    /// How much longer a shortened arc may become before it gouges
    /// (0.001 inch or 0.0254 mm).
    pub arc_slack: f64,
}

impl CompQueue {
    /// True when nothing is held back.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Drop everything (reset).
    pub fn clear(&mut self) {
        self.items.clear();
        self.endpoint_valid = false;
    }

    /// Remember where the next held move starts.
    pub fn set_endpoint(&mut self, x: f64, y: f64) {
        self.endpoint = (x, y);
        self.endpoint_valid = true;
    }

    /// The first held call, if any.
    pub fn front(&self) -> Option<&Queued> {
        self.items.first()
    }

    /// Hold a call back.
    pub fn push(&mut self, q: Queued) {
        self.items.push(q);
    }

    /// Scale held coordinates on a change of units.
    pub fn scale(&mut self, k: f64) {
        if self.items.is_empty() {
            return;
        }
        for q in &mut self.items {
            self.endpoint.0 *= k;
            self.endpoint.1 *= k;
            match q {
                Queued::ArcFeed {
                    end1,
                    end2,
                    end3,
                    center1,
                    center2,
                    rest,
                    ..
                } => {
                    *end1 *= k;
                    *end2 *= k;
                    *end3 *= k;
                    *center1 *= k;
                    *center2 *= k;
                    rest.u *= k;
                    rest.v *= k;
                    rest.w *= k;
                }
                Queued::Straight { end, .. } => {
                    end.x *= k;
                    end.y *= k;
                    end.z *= k;
                    end.u *= k;
                    end.v *= k;
                    end.w *= k;
                }
                _ => {}
            }
        }
    }

    /// Issue every held call, in order.
    pub fn dequeue(&mut self, g: CompGeometry, canon: &mut dyn Canon) {
        self.endpoint_valid = false;
        for q in self.items.drain(..) {
            issue(q, g, canon);
        }
    }

    /// Move the end point of the held moves to (x, y) (in the comp
    /// plane), checking that no move reverses, then issue them.
    pub fn move_endpoint_and_flush(
        &mut self,
        g: CompGeometry,
        x: f64,
        y: f64,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        if self.items.is_empty() {
            return Ok(());
        }
        let (ex, ey) = self.endpoint;
        let valid = self.endpoint_valid;
        for q in &mut self.items {
            match q {
                Queued::ArcFeed {
                    end1,
                    end2,
                    center1,
                    center2,
                    turn,
                    original_turns,
                    ..
                } => {
                    let r1 = (*end1 - *center1).hypot(*end2 - *center2);
                    let l1 = *original_turns;
                    let r2 = (x - *center1).hypot(y - *center2);
                    let l2 = find_turn(ex, ey, *center1, *center2, *turn, x, y);
                    if (r1 - r2).abs() > 0.01 {
                        return Err(InterpError::CompBug);
                    }
                    if l1 != 0.0 && valid && l2.abs() > l1.abs() + g.arc_slack {
                        return Err(InterpError::CompArcConcave);
                    }
                    *end1 = x;
                    *end2 = y;
                }
                Queued::Straight { feed, dir, end, .. } => {
                    let dot = dir.0 * (x - ex) + dir.1 * (y - ey);
                    if valid && dot < 0.0 {
                        return Err(if *feed {
                            InterpError::CompFeedConcave
                        } else {
                            InterpError::CompTraverseConcave
                        });
                    }
                    set_plane_xy(g.plane, end, x, y);
                }
                _ => {}
            }
        }
        self.dequeue(g, canon);
        self.set_endpoint(x, y);
        Ok(())
    }
}

/// Set the comp-plane coordinates (first, second) of a pose.
fn set_plane_xy(plane: Plane, end: &mut Pose, first: f64, second: f64) {
    if plane == Plane::Xz {
        end.z = first;
        end.x = second;
    } else {
        end.x = first;
        end.y = second;
    }
}

fn issue(q: Queued, g: CompGeometry, canon: &mut dyn Canon) {
    let (plane, o, r) = (g.plane, g.orientation, g.radius);
    match q {
        Queued::Straight {
            feed,
            line,
            mut end,
            ..
        } => {
            end.x = lathe_x(plane, o, r, end.x);
            end.z = lathe_z(plane, o, r, end.z);
            if feed {
                canon.straight_feed(line, &end);
            } else {
                canon.straight_traverse(line, &end);
            }
        }
        Queued::ArcFeed {
            line,
            end1,
            end2,
            center1,
            center2,
            turn,
            end3,
            rest,
            ..
        } => {
            let arc = Arc {
                first_end: lathe_z(plane, o, r, end1),
                second_end: lathe_x(plane, o, r, end2),
                first_axis: lathe_z(plane, o, r, center1),
                second_axis: lathe_x(plane, o, r, center2),
                rotation: turn,
                axis_end_point: end3,
                rest,
            };
            canon.arc_feed(line, &arc);
        }
        Queued::SetFeedRate(f) => canon.set_feed_rate(f),
        Queued::Dwell(t) => canon.dwell(t),
        Queued::SetFeedMode(spindle, m) => canon.set_feed_mode(spindle, m),
        Queued::MistOn => canon.mist_on(),
        Queued::MistOff => canon.mist_off(),
        Queued::FloodOn => canon.flood_on(),
        Queued::FloodOff => canon.flood_off(),
        Queued::SpindleClockwise(n) => canon.start_spindle_clockwise(n),
        Queued::SpindleCounterClockwise(n) => canon.start_spindle_counterclockwise(n),
        Queued::SpindleStop(n) => canon.stop_spindle_turning(n),
        Queued::SetSpindleMode(n, m) => canon.set_spindle_mode(n, m),
        Queued::SetSpindleSpeed(n, s) => canon.set_spindle_speed(n, s),
        Queued::Comment(c) => canon.comment(&c),
    }
}

/// Issue a non-motion call now, or hold it if moves are held.
pub(crate) fn emit(queue: &mut CompQueue, g: CompGeometry, canon: &mut dyn Canon, q: Queued) {
    if queue.is_empty() {
        issue(q, g, canon);
    } else {
        queue.push(q);
    }
}
