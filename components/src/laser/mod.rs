//! Laser cutting: laserpower (power scaled with the actual velocity) and
//! raster (power from pixel data streamed through a HAL port).

pub mod laserpower;
pub mod raster;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&laserpower::MODULE, &raster::MODULE]
}
