//! The outside world at a simulated board's connectors: what the board
//! drives into it each time step, and what it senses from it.
//!
//! The board model calls [`World::advance`] once per time step with its
//! outputs; the world moves its motors and fills in the inputs. Worlds
//! made of the shared plant models (motors, steppers, encoders, switches)
//! are in [`machine`](super::machine); [`Bench`] is a board with nothing
//! connected whose inputs a test sets by hand.

/// A PWM generator's output as a motor driver sees it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PwmOut {
    /// Duty cycle, signed by the direction output (−1..1); 0 when the
    /// generator is disabled or its pins are not driven.
    pub duty: f64,
    /// The generator is enabled and its /Enable pin driven low.
    pub enabled: bool,
    /// PWM (or PDM slot) frequency, Hz.
    pub frequency_hz: f64,
}

/// A step generator's output over one time step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StepOut {
    /// Steps that reached the connector in this time step (signed).
    pub steps: i64,
}

/// What an encoder's lines did during one time step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct EncoderIn {
    /// Quadrature count of the shaft at the end of the step.
    pub count: i64,
    /// How long before the end of the step the last edge came (ns).
    pub last_edge_ago_ns: u64,
    /// The count at the first index pulse crossed in this step.
    pub index_at: Option<i64>,
    /// A quadrature error (both lines changing at once) happened.
    pub glitch: bool,
    /// Line A at the end of the step.
    pub a: bool,
    /// Line B.
    pub b: bool,
    /// Line Z (index).
    pub z: bool,
}

/// What the board drives during one time step.
#[derive(Debug, Clone, Copy)]
pub struct Outputs<'a> {
    /// Per PWM generator.
    pub pwm: &'a [PwmOut],
    /// Per step generator.
    pub steps: &'a [StepOut],
    /// Per I/O pin: the level the board drives, `None` if the pin is an
    /// input (or open drain released).
    pub pins: &'a [Option<bool>],
}

/// What the board senses, filled in by the world.
#[derive(Debug)]
pub struct Inputs<'a> {
    /// Per encoder instance.
    pub encoders: &'a mut [EncoderIn],
    /// Per I/O pin: what the outside drives, `None` if nothing (the
    /// board's pull-up makes it read high).
    pub pins: &'a mut [Option<bool>],
}

/// The outside world of a simulated board.
pub trait World: Send + 'static {
    /// Lets `dt_ns` pass with the board driving `out`, and fills `sense`.
    fn advance(&mut self, dt_ns: u64, out: &Outputs, sense: &mut Inputs);

    /// Lets a test or tool reach the concrete world.
    fn as_any(&mut self) -> &mut dyn std::any::Any;
}

/// Nothing connected: encoder counts and pin levels stay where a test
/// puts them ([`Bench::encoders`], [`Bench::pins`]); what the board drove
/// last is kept for inspection.
#[derive(Debug, Default, Clone)]
pub struct Bench {
    /// Encoder inputs, reported as they are (counts, index, lines).
    pub encoders: Vec<EncoderIn>,
    /// Levels the outside drives per I/O pin.
    pub pins: Vec<Option<bool>>,
    /// The PWM outputs of the last step.
    pub pwm: Vec<PwmOut>,
    /// Steps received per step generator, summed.
    pub steps: Vec<i64>,
    /// The pins the board drove in the last step.
    pub driven: Vec<Option<bool>>,
}

impl World for Bench {
    fn advance(&mut self, _dt_ns: u64, out: &Outputs, sense: &mut Inputs) {
        self.pwm.clear();
        self.pwm.extend_from_slice(out.pwm);
        self.steps.resize(out.steps.len(), 0);
        for (s, o) in self.steps.iter_mut().zip(out.steps) {
            *s += o.steps;
        }
        self.driven.clear();
        self.driven.extend_from_slice(out.pins);
        for (i, e) in sense.encoders.iter_mut().enumerate() {
            if let Some(mine) = self.encoders.get_mut(i) {
                *e = *mine;
                // An index or glitch is reported once.
                mine.index_at = None;
                mine.glitch = false;
                mine.last_edge_ago_ns = 0;
            }
        }
        for (i, p) in sense.pins.iter_mut().enumerate() {
            *p = self.pins.get(i).copied().flatten();
        }
    }

    fn as_any(&mut self) -> &mut dyn std::any::Any {
        self
    }
}
