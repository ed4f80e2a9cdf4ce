//! PktUART: Mesa's packet UART, a transmitter module (GTag 0x1B) and a
//! receiver module (0x1C) whose instances pair up as `<board>.pktuart.N`.
//! The transmitter sends whole frames from a data FIFO, one frame per
//! word written to its count FIFO; the receiver cuts the line into frames
//! at an inter-frame gap and keeps each frame's size and error bits in a
//! count FIFO. `hm2_modbus` runs Modbus RTU over it.

pub mod config;
pub mod discovery;
pub mod link;
pub mod links;
pub mod port;

pub use config::{LineConfig, ModeWords};
pub use discovery::{PktUartFirmware, PktUartInstance};
pub use link::PktUartLink;
pub use port::PktUartPort;
