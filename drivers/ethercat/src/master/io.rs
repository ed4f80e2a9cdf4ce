//! EtherCrab driven without an async runtime: its futures are polled in
//! a loop that sends the frames it queued over a [`Link`] and feeds back
//! the frames that arrive.

use std::future::Future;
use std::pin::pin;
use std::task::{Context, Poll, Waker};
use std::time::Duration;

use ethercrab::{PduRx, PduTx};

use crate::link::Link;

/// EtherCrab's frame queue and the link, pumped by [`Io::block_on`].
pub(crate) struct Io<'sto> {
    pub(crate) tx: PduTx<'sto>,
    pub(crate) rx: PduRx<'sto>,
    pub(crate) link: Box<dyn Link>,
    pub(crate) buf: Vec<u8>,
}

impl Io<'_> {
    /// Sends what EtherCrab queued and takes in what came back.
    pub(crate) fn pump(&mut self, wait: Duration) {
        while let Some(frame) = self.tx.next_sendable_frame() {
            let link = &mut self.link;
            let _ = frame.send_blocking(|d| {
                link.send(d)
                    .map_err(|_| ethercrab::error::Error::SendFrame)?;
                Ok(d.len())
            });
        }
        if let Ok(Some(n)) = self.link.recv(&mut self.buf, wait) {
            let _ = self.rx.receive_frame(&self.buf[..n]);
        }
    }

    /// Runs a future of EtherCrab's to completion.
    pub(crate) fn block_on<F: Future>(&mut self, fut: F) -> F::Output {
        let mut fut = pin!(fut);
        let mut cx = Context::from_waker(Waker::noop());
        loop {
            if let Poll::Ready(v) = fut.as_mut().poll(&mut cx) {
                return v;
            }
            self.pump(Duration::from_micros(200));
        }
    }
}
