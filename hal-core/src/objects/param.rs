//! Parameters: creation and access by name.

use std::sync::atomic::Ordering::*;

use super::list;
use super::Instance;
use crate::error::{HalError, Result};
use crate::name::validate;
use crate::shm::*;
use crate::types::{HalType, ParamDir, Value};

pub(crate) fn param_type(seg: &Segment, p: &ParamRec) -> Result<HalType> {
    HalType::from_code(p.type_code.load(Relaxed) as u32).ok_or_else(|| HalError::BadSegment {
        instance: seg.instance().to_string(),
        reason: format!("param '{}' has an unknown type code", p.name.get()),
    })
}

pub(crate) fn param_dir(p: &ParamRec) -> ParamDir {
    ParamDir::from_code(p.dir.load(Relaxed) as u32).unwrap_or(ParamDir::Ro)
}

/// Finds a param by name or by its name before aliasing.
pub(crate) fn find_param<'a>(seg: &'a Segment, name: &str) -> Result<Option<(u64, &'a ParamRec)>> {
    list::find_aliased(seg, &seg.header().params, name)
}

fn require_param<'a>(seg: &'a Segment, name: &str) -> Result<(u64, &'a ParamRec)> {
    find_param(seg, name)?.ok_or_else(|| HalError::NotFound {
        kind: "param",
        name: name.to_string(),
    })
}

impl Instance {
    pub(crate) fn new_param(
        &self,
        comp: u64,
        name: &str,
        t: HalType,
        dir: ParamDir,
        init: u64,
    ) -> Result<u64> {
        self.tx(|tx| new_param_tx(tx, comp, name, t, dir, init))
    }

    /// Reads a param's value (halcmd `getp` on a param).
    pub fn param_value(&self, name: &str) -> Result<Value> {
        self.tx(|tx| {
            let seg = tx.seg();
            let (_, p) = require_param(seg, name)?;
            Ok(Value::from_bits(
                param_type(seg, p)?,
                p.words(seg)?.first.load(Relaxed),
            ))
        })
    }

    /// Sets a read-write param (halcmd `setp` on a param).
    pub fn set_param(&self, name: &str, value: Value) -> Result<()> {
        self.check_unlocked(super::lock_bits::PARAMS, "param_set")?;
        self.tx(|tx| {
            let seg = tx.seg();
            let (_, p) = require_param(seg, name)?;
            let t = param_type(seg, p)?;
            if t != value.hal_type() {
                return Err(HalError::WrongType {
                    kind: "param",
                    name: name.to_string(),
                    expected: value.hal_type(),
                    actual: t,
                });
            }
            if param_dir(p) == ParamDir::Ro {
                return Err(HalError::ParamReadOnly { name: p.name.get() });
            }
            p.words(seg)?.first.store(value.to_bits(), Relaxed);
            Ok(())
        })
    }
}

pub(crate) fn new_param_tx(
    tx: &mut Txn<'_>,
    comp: u64,
    name: &str,
    t: HalType,
    dir: ParamDir,
    init: u64,
) -> Result<u64> {
    validate("param", name)?;
    if t == HalType::Port {
        return Err(HalError::NotAPortMaker {
            name: name.to_string(),
        });
    }
    let seg = tx.seg();
    let h = tx.header();
    if find_param(seg, name)?.is_some() {
        return Err(HalError::Duplicate {
            kind: "param",
            name: name.to_string(),
        });
    }
    let (off, rec) = tx.alloc::<ParamRec>(BlockKind::Param)?;
    rec.name.init(name);
    rec.type_code.store(t.code() as u64, Relaxed);
    rec.dir.store(dir.code() as u64, Relaxed);
    rec.owner.store(comp, Relaxed);
    rec.hot
        .store(tx.alloc_pair(PairPool::Param, init, 0)?, Relaxed);
    list::insert_sorted(tx, &h.params, off, rec)?;
    super::component::adopt(tx, comp, |c| &c.own_params, &rec.owner_next, off)?;
    Ok(off)
}
