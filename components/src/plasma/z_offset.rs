//! The Z offset both torch height controllers keep: moved by a fixed
//! step per period while cutting, taken back while the torch is off and Z
//! rises. Single precision, as LinuxCNC's `float` variables are.

/// The offset and the Z it last saw.
#[derive(Debug, Clone, Default)]
pub struct ZOffset {
    /// The offset added to the Z command.
    pub offset: f32,
    last_z_in: f32,
}

impl ZOffset {
    /// One correcting period: `down` lowers the torch by `step`, `up`
    /// raises it (both may apply).
    pub fn correct(&mut self, down: bool, up: bool, step: f64) {
        if down {
            self.offset = (f64::from(self.offset) - step) as f32;
        }
        if up {
            self.offset = (f64::from(self.offset) + step) as f32;
        }
        self.last_z_in = 0.0;
    }

    /// One period with the torch off at Z `z`: as Z rises, the offset
    /// shrinks by the rise (a positive one) or grows by it (a negative
    /// one, which may overshoot past zero: LinuxCNC's rule). Returns TRUE
    /// while taking the offset back.
    pub fn take_back(&mut self, z: f64) -> bool {
        let z_diff = (z - f64::from(self.last_z_in)) as f32;
        let removing = z_diff > 0.0 && self.offset != 0.0;
        if removing {
            if self.offset > 0.0 {
                self.offset = if self.offset > z_diff {
                    self.offset - z_diff
                } else {
                    0.0
                };
            }
            if self.offset < 0.0 {
                self.offset = if self.offset < z_diff {
                    self.offset + z_diff
                } else {
                    0.0
                };
            }
        }
        self.last_z_in = z as f32;
        removing
    }

    /// The Z command with the offset.
    pub fn z_out(&self, z: f64) -> f64 {
        z + f64::from(self.offset)
    }
}
