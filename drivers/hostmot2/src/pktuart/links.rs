//! The PktUART links a board carries in its bursts ([`PktUartLink`]):
//! attached and detached at load time, serviced by the board's `read`
//! (their reads after the TRAM regions, in one burst) and `write` (their
//! staged writes after the board's own).

use super::discovery::PktUartInstance;
use super::link::{PktUartLink, BURST_READS, BURST_WRITES};
use crate::error::Hm2Error;
use crate::transport::{Transport, TransportError};

/// A link and whether its user still has it (a detached link whose
/// reads are in the burst under way stays until they come).
#[derive(Debug)]
struct Slot {
    link: PktUartLink,
    live: bool,
}

/// Every link of one board, and the buffer their burst lands in.
#[derive(Debug, Default)]
pub struct Links {
    slots: Vec<Option<Slot>>,
    /// The whole read burst: TRAM words, then the links' words.
    burst: Vec<u32>,
    /// Link words in the burst under way.
    carried: usize,
}

impl Links {
    /// Attaches a link to `inst` (load time), sizing the burst buffer
    /// for `tram_words` TRAM words before the links'; its id.
    pub fn attach(&mut self, inst: &PktUartInstance, tram_words: usize) -> Result<usize, Hm2Error> {
        let taken = |s: &Slot| s.live && s.link.instance().rx == inst.rx;
        if self.slots.iter().flatten().any(taken) {
            return Err(Hm2Error::PktUartInUse {
                port: inst.name.clone(),
            });
        }
        let link = Some(Slot {
            link: PktUartLink::new(inst.clone()),
            live: true,
        });
        let id = match self.slots.iter().position(Option::is_none) {
            Some(free) => {
                self.slots[free] = link;
                free
            }
            None => {
                self.slots.push(link);
                self.slots.len() - 1
            }
        };
        self.burst
            .resize(tram_words + BURST_READS * self.slots.len(), 0);
        Ok(id)
    }

    /// Detaches link `id` (load time); its slot is reused.
    pub fn detach(&mut self, id: usize) {
        if let Some(s) = self.slots.get_mut(id) {
            match s {
                Some(slot) if slot.link.carried_words() > 0 => slot.live = false,
                _ => *s = None,
            }
        }
    }

    /// Link `id`, if attached.
    #[inline]
    pub fn get(&mut self, id: usize) -> Option<&mut PktUartLink> {
        self.slots
            .get_mut(id)?
            .as_mut()
            .filter(|s| s.live)
            .map(|s| &mut s.link)
    }

    /// Whether the burst under way carries link reads.
    #[inline]
    pub fn carrying(&self) -> bool {
        self.carried > 0
    }

    /// What the links add to a transport's per-cycle queues at most:
    /// (reads, read words, writes, write words).
    pub fn reserve_sizes(&self) -> (usize, usize, usize, usize) {
        let n = self.slots.len();
        (
            n * BURST_READS,
            n * BURST_READS,
            n * BURST_WRITES,
            n * BURST_WRITES,
        )
    }

    /// Queues every link's reads (after the TRAM regions), as many as
    /// the transport takes: never fails the board's burst.
    pub fn queue_reads(&mut self, t: &mut dyn Transport) {
        self.carried = 0;
        for s in self.slots.iter_mut().flatten().filter(|s| s.live) {
            self.carried += s.link.queue_reads(t);
        }
    }

    /// Receives the burst: the TRAM words into `tram`, the rest to the
    /// links. On failure the links learn their reads were lost.
    pub fn receive(
        &mut self,
        t: &mut dyn Transport,
        tram: &mut [u32],
    ) -> Result<(), TransportError> {
        let n = tram.len();
        let Some(buf) = self.burst.get_mut(..n + self.carried) else {
            // Sized at attach, so never; the transport empties its queue.
            self.lost();
            return t.receive_queued_reads(&mut []);
        };
        if let Err(e) = t.receive_queued_reads(buf) {
            self.lost();
            return Err(e);
        }
        tram.copy_from_slice(&buf[..n]);
        let mut at = n;
        for s in self.slots.iter_mut().flatten() {
            // A link's words: what it queued (count, data, two status).
            let words = s.link.carried_words();
            s.link.take_reads(&buf[at..at + words]);
            at += words;
        }
        self.carried = 0;
        self.retire();
        Ok(())
    }

    /// The burst under way was lost.
    pub fn lost(&mut self) {
        for s in self.slots.iter_mut().flatten() {
            s.link.reads_lost();
        }
        self.carried = 0;
        self.retire();
    }

    /// Queues every link's staged writes, as many as the transport
    /// takes (the rest wait for the next burst): never fails the board's
    /// burst.
    pub fn queue_writes(&mut self, t: &mut dyn Transport) {
        for s in self.slots.iter_mut().flatten() {
            s.link.queue_writes(t);
        }
    }

    /// Frees the slots of detached links (no allocation).
    fn retire(&mut self) {
        for s in &mut self.slots {
            if s.as_ref().is_some_and(|s| !s.live) {
                *s = None;
            }
        }
    }
}
