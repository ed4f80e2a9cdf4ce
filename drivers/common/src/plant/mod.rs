//! Models of the outside world a simulated board drives and senses.
//! Every simulated board (parport's loopback, hostmot2, motenc, stg, the
//! CiA 402 drive) moves its motors through these, never its own copy, so
//! a motor behaves the same behind every driver.
//!
//! * [`DcMotor`]: drive voltage or PWM duty → velocity → position, with
//!   inertia, friction and a settable load.
//! * [`StepperAxis`]: step/dir pulses or a step rate → position.
//! * [`ServoAxis`]: a [`DcMotor`] with a [`QuadEncoder`] on its shaft,
//!   driven by a servo card's output voltage.
//! * [`QuadEncoder`]: shaft position → A/B/Z levels, count edges and the
//!   index pulse once per revolution.
//! * [`Switch`]: home and limit switches at positions.
//!
//! Models are plain values with no locking: a board model owns them and
//! advances them in its own
//! [`BoardModel::advance`](crate::sim::BoardModel::advance). A motor driving an encoder:
//!
//! ```
//! use hal_driver::plant::{DcMotor, DcMotorParams, QuadEncoder};
//!
//! let mut motor = DcMotor::new(DcMotorParams { speed_per_volt: 1.0, time_constant: 0.02, friction: 0.1 });
//! let mut enc = QuadEncoder::new(4000); // 1000 lines
//! motor.set_duty(0.5, 24.0);            // PWM at 50 % of 24 V
//! motor.advance(1_000_000_000);          // one second
//! let moved = enc.set_revs(motor.position()); // position in revolutions
//! assert!(moved.delta > 40_000 && moved.index_pulses >= 10);
//! ```

mod encoder;
mod motor;
mod servo;
mod stepper;
mod switch;

pub use encoder::{EncoderMove, QuadEncoder};
pub use motor::{DcMotor, DcMotorParams};
pub use servo::{ServoAxis, SMALL_SERVO};
pub use stepper::StepperAxis;
pub use switch::Switch;
