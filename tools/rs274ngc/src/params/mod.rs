//! Parameters: the numbered ones (#1 to #5601) and the named ones
//! (`#<name>` local to a subroutine level, `#<_name>` global).
//!
//! The predefined read-only named parameters (`#<_x>`, `#<_line>`, ...)
//! depend on the interpreter's state; they are answered by
//! [`crate::interp::Interp`], not stored here.

pub mod file;

use std::collections::HashMap;

use crate::error::{InterpError, Result};

/// One past the highest parameter number (#5601 is the last).
pub const MAX_PARAMETERS: usize = 5602;

/// Subroutine nesting levels (level 0 is the main program).
pub const CALL_LEVELS: usize = 10;

/// True for the numbered parameters a program may not assign.
pub fn is_readonly(index: i32) -> bool {
    (5400..=5413).contains(&index) || (5420..=5428).contains(&index)
}

/// A named parameter's value and whether it was ever assigned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Named {
    /// The value (0 until assigned).
    pub value: f64,
    /// Created by a pending assignment on the line being read, not yet
    /// given its value.
    pub unset: bool,
}

/// The parameter store.
#[derive(Debug, Clone)]
pub struct Parameters {
    numbered: Vec<f64>,
    /// Named parameters per call level; globals live at level 0.
    named: Vec<HashMap<String, Named>>,
}

impl Default for Parameters {
    fn default() -> Self {
        Parameters {
            numbered: vec![0.0; MAX_PARAMETERS],
            named: vec![HashMap::new(); CALL_LEVELS + 1],
        }
    }
}

impl Parameters {
    /// The value of numbered parameter `index` (must be in range).
    pub fn get(&self, index: usize) -> f64 {
        self.numbered.get(index).copied().unwrap_or(0.0)
    }

    /// Set numbered parameter `index`; out-of-range indices are ignored
    /// (callers check the range first and report it).
    pub fn set(&mut self, index: usize, value: f64) {
        if let Some(slot) = self.numbered.get_mut(index) {
            *slot = value;
        }
    }

    /// The numbered parameters as a slice (index 0 unused).
    pub fn numbered(&self) -> &[f64] {
        &self.numbered
    }

    /// The scope level a name lives at: 0 for globals (`_name`), the
    /// current call level for locals.
    fn level_of(name: &str, call_level: usize) -> usize {
        if name.starts_with('_') {
            0
        } else {
            call_level.min(CALL_LEVELS)
        }
    }

    /// Look a named parameter up in its scope.
    pub fn find_named(&self, name: &str, call_level: usize) -> Option<Named> {
        self.named[Self::level_of(name, call_level)]
            .get(name)
            .copied()
    }

    /// Create a named parameter (value 0, marked unset) if it does not
    /// exist yet in its scope; this is what reading `#<name>=` does.
    pub fn add_named(&mut self, name: &str, call_level: usize) {
        let level = Self::level_of(name, call_level);
        self.named[level].entry(name.to_string()).or_insert(Named {
            value: 0.0,
            unset: true,
        });
    }

    /// Assign a named parameter created by [`Parameters::add_named`].
    pub fn store_named(&mut self, name: &str, value: f64, call_level: usize) -> Result<()> {
        let level = Self::level_of(name, call_level);
        let slot = self.named[level].entry(name.to_string()).or_insert(Named {
            value: 0.0,
            unset: true,
        });
        slot.value = value;
        slot.unset = false;
        Ok(())
    }

    /// Forget the local named parameters of a call level (on return).
    pub fn clear_level(&mut self, level: usize) {
        if let Some(scope) = self.named.get_mut(level) {
            scope.clear();
        }
    }

    /// Check a numbered parameter index for an assignment or a read.
    pub fn check_index(index: i32) -> Result<usize> {
        if index < 1 || index as usize >= MAX_PARAMETERS {
            return Err(InterpError::ParameterOutOfRange);
        }
        Ok(index as usize)
    }
}
