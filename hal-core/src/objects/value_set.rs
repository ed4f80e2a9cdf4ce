//! Many values read together, often: a list of pins, parameters and
//! signals found by name once, then read in one short hold of the HAL
//! lock per pass, one load per value. The words are found again only after
//! a structural change (the instance's generation moved), so a pass costs
//! no name lookup, no allocation and no text. For tools that show live
//! values (hal-web's watch lists), where reading the whole `show` at each
//! refresh would cost far more than the values.

use std::sync::atomic::Ordering::*;

use super::Instance;
use crate::error::Result;
use crate::shm::*;
use crate::types::{HalType, Value};

/// What kind of object a name in a [`ValueSet`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ValueKind {
    /// A pin: its own value, or its signal's once linked.
    Pin,
    /// A parameter.
    Param,
    /// A signal.
    Signal,
}

/// A list of names whose values are read together by
/// [`Instance::read_values`].
#[derive(Debug, Clone)]
pub struct ValueSet {
    names: Vec<(ValueKind, String)>,
    /// The generation `words` were found at (None: not yet).
    found_at: Option<u64>,
    /// Per name, the offset of the word holding its value and its type;
    /// None for a name the instance does not have.
    words: Vec<Option<(u64, HalType)>>,
}

impl ValueSet {
    /// A set of `names`, read in this order.
    pub fn new(names: impl IntoIterator<Item = (ValueKind, String)>) -> ValueSet {
        ValueSet {
            names: names.into_iter().collect(),
            found_at: None,
            words: Vec::new(),
        }
    }

    /// How many names the set has.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Whether the set has no names.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// Finds the word of every name (the HAL lock is held).
    fn find(&mut self, seg: &Segment) -> Result<()> {
        self.words.clear();
        for (kind, name) in &self.names {
            self.words.push(word_of(seg, *kind, name)?);
        }
        Ok(())
    }
}

/// The offset of the word holding the value of `name` (a pin's current
/// cell: its own, or its signal's) and its type; None when the instance
/// has no such object. The HAL lock is held.
fn word_of(seg: &Segment, kind: ValueKind, name: &str) -> Result<Option<(u64, HalType)>> {
    Ok(match kind {
        ValueKind::Pin => match super::pin::find_pin(seg, name)? {
            Some((_, p)) => Some((
                p.words(seg)?.first.load(Relaxed),
                super::pin::pin_type(seg, p)?,
            )),
            None => None,
        },
        ValueKind::Param => match super::param::find_param(seg, name)? {
            Some((_, p)) => Some((
                seg.offset_of(&p.words(seg)?.first),
                super::param::param_type(seg, p)?,
            )),
            None => None,
        },
        ValueKind::Signal => match super::list::find::<SigRec>(seg, &seg.header().signals, name)? {
            Some((_, s)) => {
                let cell: &CellRec = seg.rec(s.cell.load(Relaxed))?;
                Some((seg.offset_of(&cell.value), super::signal::sig_type(seg, s)?))
            }
            None => None,
        },
    })
}

impl Instance {
    /// Where the value of `name` lives now, as an offset in the segment,
    /// with the instance's generation it was found at and the value's
    /// type; None when the instance has no such object. The offset stays
    /// good while the generation stands (a `net` or `unlinkp` moves a
    /// pin's value to another cell). For a [`crate::CellReader`].
    pub fn value_word(&self, kind: ValueKind, name: &str) -> Result<Option<(u64, u64, HalType)>> {
        self.tx(|tx| {
            let seg = tx.seg();
            let generation = seg.header().generation.load(Acquire);
            Ok(word_of(seg, kind, name)?.map(|(off, t)| (off, generation, t)))
        })
    }

    /// Reads the current value of every name of `set` into `out` (cleared
    /// first, then one entry per name in order; None for a name the
    /// instance does not have). One hold of the HAL lock; names are
    /// looked up only on the first read and after structural changes.
    pub fn read_values(&self, set: &mut ValueSet, out: &mut Vec<Option<Value>>) -> Result<()> {
        out.clear();
        self.tx(|tx| {
            let seg = tx.seg();
            // Under the lock the generation stands still: what was found
            // at this generation is still where it was.
            let generation = seg.header().generation.load(Acquire);
            if set.found_at != Some(generation) {
                set.found_at = None;
                set.find(seg)?;
                set.found_at = Some(generation);
            }
            for word in &set.words {
                out.push(match word {
                    Some((off, t)) => Some(Value::from_bits(*t, seg.word(*off)?.load(Relaxed))),
                    None => None,
                });
            }
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ComponentKind, Host, HostConfig, In, Out, Rw};

    fn set_of(names: &[(ValueKind, &str)]) -> ValueSet {
        ValueSet::new(names.iter().map(|(k, n)| (*k, n.to_string())))
    }

    #[test]
    fn values_follow_writes_links_and_removals() {
        let host = Host::create(HostConfig::for_tests("value-set")).unwrap();
        let inst = host.instance();
        let comp = inst.new_component("vs", ComponentKind::User).unwrap();
        let a = comp.pin::<f64, Out>("vs.a").unwrap();
        let _b = comp.pin::<f64, In>("vs.b").unwrap();
        let _p = comp.param::<i32, Rw>("vs.p", 7).unwrap();
        comp.ready().unwrap();
        let mut set = set_of(&[
            (ValueKind::Pin, "vs.a"),
            (ValueKind::Pin, "vs.b"),
            (ValueKind::Param, "vs.p"),
            (ValueKind::Signal, "s"),
            (ValueKind::Pin, "vs.none"),
        ]);
        let mut out = Vec::new();
        a.set(1.5);
        inst.read_values(&mut set, &mut out).unwrap();
        assert_eq!(
            out,
            vec![
                Some(Value::Float(1.5)),
                Some(Value::Float(0.0)),
                Some(Value::S32(7)),
                None,
                None
            ]
        );
        // A link moves vs.b's value to the signal's cell: found again.
        inst.newsig("s", HalType::Float).unwrap();
        inst.link("vs.a", "s").unwrap();
        inst.link("vs.b", "s").unwrap();
        a.set(2.5);
        inst.read_values(&mut set, &mut out).unwrap();
        assert_eq!(out[0], Some(Value::Float(2.5)));
        assert_eq!(out[1], Some(Value::Float(2.5)));
        assert_eq!(out[3], Some(Value::Float(2.5)));
        // Removed objects read as missing.
        inst.delsig("s").unwrap();
        drop((a, _b, _p, comp));
        inst.read_values(&mut set, &mut out).unwrap();
        assert_eq!(out, vec![None; 5]);
    }

    #[test]
    fn a_cell_reader_reads_value_words_and_never_outside_the_cells() {
        let host = Host::create(HostConfig::for_tests("cell-reader")).unwrap();
        let inst = host.instance();
        let comp = inst.new_component("cr", ComponentKind::User).unwrap();
        let a = comp.pin::<f64, Out>("cr.a").unwrap();
        let region = comp.region("cr.words", 64).unwrap();
        comp.ready().unwrap();
        let reader = region.cell_reader();
        let (off, generation, t) = inst.value_word(ValueKind::Pin, "cr.a").unwrap().unwrap();
        assert_eq!((t, generation), (HalType::Float, inst.generation()));
        a.set(2.5);
        assert_eq!(f64::from_bits(reader.read(off)), 2.5);
        // Linked, the pin's value lives in the signal's cell: a new word,
        // found at a new generation.
        inst.newsig("s", HalType::Float).unwrap();
        inst.link("cr.a", "s").unwrap();
        let (moved, later, _) = inst.value_word(ValueKind::Pin, "cr.a").unwrap().unwrap();
        assert!(moved != off && later != generation);
        a.set(-1.0);
        assert_eq!(f64::from_bits(reader.read(moved)), -1.0);
        assert_eq!(
            inst.value_word(ValueKind::Signal, "s").unwrap().unwrap().0,
            moved
        );
        assert!(inst
            .value_word(ValueKind::Pin, "cr.none")
            .unwrap()
            .is_none());
        // Offsets that name no cell (past the end, misaligned, zero) read
        // a cell of the segment, never outside it.
        for bad in [u64::MAX, off + 3, 0, 1 << 40] {
            let _ = reader.read(bad);
        }
    }
}
