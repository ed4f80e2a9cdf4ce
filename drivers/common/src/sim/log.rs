//! [`AccessLog`]: what a driver did to a simulated board, in order, so
//! tests can assert access order and counts ("writes only on change",
//! "the timestamp is read before the counters").

use std::collections::VecDeque;

/// How wide an access is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Width {
    /// 8 bits (`inb`/`outb`).
    Byte,
    /// 16 bits (`inw`/`outw`).
    Word,
    /// 32 bits (`inl`/`outl`, `read32`/`write32`).
    Long,
}

impl Width {
    /// The width in bytes.
    pub fn bytes(self) -> u16 {
        match self {
            Width::Byte => 1,
            Width::Word => 2,
            Width::Long => 4,
        }
    }
}

/// Read or write.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Dir {
    /// The driver read.
    Read,
    /// The driver wrote.
    Write,
}

/// One logged access.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Access {
    /// When, on the board's time (or the clock it stamps with), in ns.
    pub time_ns: u64,
    /// The byte offset (memory window) or absolute port (port bus).
    pub addr: u64,
    /// How wide.
    pub width: Width,
    /// The value read or written.
    pub value: u32,
    /// Read or write.
    pub dir: Dir,
}

impl Access {
    /// Whether it is a write.
    pub fn is_write(&self) -> bool {
        self.dir == Dir::Write
    }
}

/// A bounded log keeping the newest accesses. Its buffer is allocated up
/// front, so recording never allocates.
#[derive(Debug, Clone)]
pub struct AccessLog {
    records: VecDeque<Access>,
    capacity: usize,
    /// Accesses recorded since the last clear, including those the
    /// buffer no longer holds.
    total: u64,
    reads: bool,
    writes: bool,
}

impl AccessLog {
    /// A log of reads and writes keeping the newest `capacity` (at least
    /// 1).
    pub fn new(capacity: usize) -> AccessLog {
        let capacity = capacity.max(1);
        AccessLog {
            records: VecDeque::with_capacity(capacity),
            capacity,
            total: 0,
            reads: true,
            writes: true,
        }
    }

    /// A log of writes only (reads, which a polling driver makes many of,
    /// would crowd them out).
    pub fn writes_only(capacity: usize) -> AccessLog {
        AccessLog {
            reads: false,
            ..AccessLog::new(capacity)
        }
    }

    /// Whether accesses in direction `dir` are recorded.
    #[inline]
    pub fn wants(&self, dir: Dir) -> bool {
        match dir {
            Dir::Read => self.reads,
            Dir::Write => self.writes,
        }
    }

    /// Records an access (if its direction is wanted), dropping the
    /// oldest when full.
    #[inline]
    pub fn record(&mut self, access: Access) {
        if !self.wants(access.dir) {
            return;
        }
        if self.records.len() == self.capacity {
            self.records.pop_front();
        }
        self.records.push_back(access);
        self.total += 1;
    }

    /// The accesses held, oldest first.
    pub fn records(&self) -> impl Iterator<Item = &Access> {
        self.records.iter()
    }

    /// How many accesses were recorded since the last clear (the buffer
    /// may hold fewer).
    pub fn total(&self) -> u64 {
        self.total
    }

    /// Forgets everything.
    pub fn clear(&mut self) {
        self.records.clear();
        self.total = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn a(addr: u64, dir: Dir) -> Access {
        Access {
            time_ns: addr * 10,
            addr,
            width: Width::Long,
            value: addr as u32,
            dir,
        }
    }

    #[test]
    fn keeps_the_newest_and_counts_all() {
        let mut l = AccessLog::new(2);
        for i in 0..5 {
            l.record(a(i, Dir::Write));
        }
        assert_eq!(l.records().map(|r| r.addr).collect::<Vec<_>>(), vec![3, 4]);
        assert_eq!(l.total(), 5);
        l.clear();
        assert_eq!((l.records().count(), l.total()), (0, 0));
        let mut w = AccessLog::writes_only(4);
        w.record(a(1, Dir::Read));
        w.record(a(2, Dir::Write));
        assert_eq!(w.records().map(|r| r.addr).collect::<Vec<_>>(), vec![2]);
        assert!(!w.wants(Dir::Read) && w.wants(Dir::Write));
    }
}
