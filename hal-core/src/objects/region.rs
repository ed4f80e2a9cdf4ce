//! Named memory regions that components allocate in the segment (LinuxCNC's
//! hal_malloc and rtapi_shmem), visible to every process by name.

use std::sync::atomic::{AtomicU64, Ordering::*};
use std::sync::Arc;

use super::component::Component;
use super::list;
use super::Instance;
use crate::error::{HalError, Result};
use crate::name::validate;
use crate::shm::*;

/// A region of shared words. Contents start zeroed.
#[derive(Clone)]
pub struct Region {
    seg: Arc<Segment>,
    data_off: u64,
    words: usize,
    name: String,
}

impl Region {
    /// The region's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The region's words, shared with every process of the instance.
    pub fn words(&self) -> &[AtomicU64] {
        // Checked when the region was opened; the segment outlives `self`.
        self.seg
            .words(self.data_off, self.words as u64)
            .unwrap_or(&[])
    }

    /// Size in bytes.
    pub fn len_bytes(&self) -> usize {
        self.words * 8
    }

    /// A reader of the instance's value cells by offset (see
    /// [`Instance::value_word`]), for realtime code that samples values a
    /// tool chose through this region.
    pub fn cell_reader(&self) -> crate::handles::CellReader {
        crate::handles::CellReader::new(&self.seg)
    }
}

impl Component {
    /// Allocates a named region of at least `bytes` bytes, owned by this
    /// component and freed with it.
    pub fn region(&self, name: &str, bytes: usize) -> Result<Region> {
        validate("region", name)?;
        let comp = self.offset();
        let inst = self.instance();
        let words = bytes.div_ceil(8).max(1);
        let off = inst.tx(|tx| {
            let h = tx.header();
            if list::find::<RegionRec>(tx.seg(), &h.regions, name)?.is_some() {
                return Err(HalError::Duplicate {
                    kind: "region",
                    name: name.to_string(),
                });
            }
            let (blob, b) = tx.alloc_blob(words as u64 * 8)?;
            b.len.store(words as u64 * 8, Relaxed);
            let (off, r) = tx.alloc::<RegionRec>(BlockKind::Region)?;
            r.name.init(name);
            r.owner.store(comp, Relaxed);
            r.blob.store(blob, Relaxed);
            r.size.store(words as u64 * 8, Relaxed);
            list::insert_sorted(tx, &h.regions, off, r)?;
            super::component::adopt(tx, comp, |c| &c.own_regions, &r.owner_next, off)?;
            Ok(off)
        })?;
        inst.open_region_at(off)
    }
}

impl Instance {
    /// Opens an existing region by name.
    pub fn region(&self, name: &str) -> Result<Region> {
        let off = self.tx(|tx| {
            let h = tx.header();
            list::find::<RegionRec>(tx.seg(), &h.regions, name)?
                .map(|(o, _)| o)
                .ok_or_else(|| HalError::NotFound {
                    kind: "region",
                    name: name.to_string(),
                })
        })?;
        self.open_region_at(off)
    }

    fn open_region_at(&self, off: u64) -> Result<Region> {
        let r: &RegionRec = self.seg.rec(off)?;
        let blob = r.blob.load(Relaxed);
        let size = r.size.load(Relaxed);
        let data = crate::shm::blob_words_of(&self.seg, blob)?;
        if (data.len() as u64) * 8 < size {
            return Err(HalError::BadOffset {
                offset: blob,
                size: self.seg.size(),
            });
        }
        let data_off = self.seg.offset_of(&data[0]);
        Ok(Region {
            seg: self.seg.clone(),
            data_off,
            words: (size / 8) as usize,
            name: r.name.get(),
        })
    }
}
