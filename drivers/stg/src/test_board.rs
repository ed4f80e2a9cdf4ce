//! The simulated board the unit tests drive: a board at 0x300 and the
//! driver on it.

use std::sync::Arc;

use hal_driver::sim::{AccessLog, SimBoard, SimClock};

use crate::detect::Model;
use crate::dio::Dio;
use crate::driver::Stg;
use crate::sim::StgModel;

/// A simulated `model` at 0x300 with ports `dio`, recording into `log`
/// if given, and the driver on it (not initialised yet).
pub(crate) fn board(
    model: Model,
    dio: &str,
    log: Option<AccessLog>,
) -> (Arc<SimBoard<StgModel>>, Stg) {
    let mut sim = SimBoard::new(StgModel::new(model, 0x300));
    if let Some(log) = log {
        sim = sim.with_log(log);
    }
    let sim = Arc::new(sim);
    let drv = Stg::new(
        sim.clone(),
        0x300,
        model,
        Dio::parse(dio).unwrap(),
        Arc::new(SimClock::new(0, 1_000)),
    );
    (sim, drv)
}
