//! Capture and plots, headless: [`scope`] (halscope: triggered captures
//! of pins and signals through a sampler, written as text, CSV, VCD or a
//! PNG plot), [`latency`] (latency-test: thread timing measured on a live
//! host, its report and histogram plot), [`motion_plot`] (motion-plot: a
//! sampled motion run's summary and plot), [`fifo`] (the sampler and
//! streamer FIFOs that halsampler and halstreamer read and fill) and
//! [`plot`] (PNG plots with a built-in font, no font files needed).

#![forbid(unsafe_code)]

mod error;
pub mod fifo;
pub mod latency;
pub mod motion_plot;
pub mod plot;
pub mod scope;

pub use error::{Cause, ScopeError};
