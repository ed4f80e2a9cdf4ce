//! Infrastructure components: thread creation and the sampler/streamer
//! FIFOs between realtime and user space, and scope_rt (halscope's
//! realtime half).

pub mod columns;
pub mod sampler;
pub mod scope_rt;
pub mod streamer;
pub mod threads;
pub mod threadtest;
