//! Infrastructure components: thread creation and the sampler/streamer
//! FIFOs between realtime and user space.

pub mod columns;
pub mod sampler;
pub mod streamer;
pub mod threads;
pub mod threadtest;
