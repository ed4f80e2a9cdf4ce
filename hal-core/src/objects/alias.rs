//! Aliases: a pin or param gets a new name; the old one is kept so that it
//! can be found by either and `unalias` can restore it.

use super::list::{self, Aliased};
use super::param::find_param;
use super::pin::find_pin;
use super::Instance;
use crate::error::{HalError, Result};
use crate::name::validate;
use crate::shm::*;

/// Which kind of object an alias applies to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AliasKind {
    /// `alias pin`.
    Pin,
    /// `alias param`.
    Param,
}

impl Instance {
    /// Gives a pin or param a new name (halcmd `alias`). Aliasing an
    /// aliased object replaces the alias; the original name is kept.
    pub fn alias(&self, kind: AliasKind, name: &str, alias: &str) -> Result<()> {
        self.check_unlocked(super::lock_bits::CONFIG, alias_op(kind))?;
        validate(kind_name(kind), alias)?;
        self.tx(|tx| {
            let seg = tx.seg();
            let h = tx.header();
            match kind {
                AliasKind::Pin => {
                    if find_pin(seg, alias)?.is_some() {
                        return Err(dup(kind, alias));
                    }
                    let (off, p) = find_pin(seg, name)?.ok_or_else(|| missing(kind, name))?;
                    rename(tx, &h.pins, off, p, alias)
                }
                AliasKind::Param => {
                    if find_param(seg, alias)?.is_some() {
                        return Err(dup(kind, alias));
                    }
                    let (off, p) = find_param(seg, name)?.ok_or_else(|| missing(kind, name))?;
                    rename(tx, &h.params, off, p, alias)
                }
            }
        })
    }

    /// Restores the original name of an aliased pin or param (halcmd
    /// `unalias`); `name` may be the alias or the original name.
    pub fn unalias(&self, kind: AliasKind, name: &str) -> Result<()> {
        self.check_unlocked(super::lock_bits::CONFIG, alias_op(kind))?;
        self.tx(|tx| {
            let seg = tx.seg();
            let h = tx.header();
            match kind {
                AliasKind::Pin => {
                    let (off, p) = find_pin(seg, name)?.ok_or_else(|| missing(kind, name))?;
                    restore(tx, &h.pins, off, p)
                }
                AliasKind::Param => {
                    let (off, p) = find_param(seg, name)?.ok_or_else(|| missing(kind, name))?;
                    restore(tx, &h.params, off, p)
                }
            }
        })
    }
}

fn rename<T: Aliased>(
    tx: &mut Txn<'_>,
    head: &ObjList,
    off: u64,
    rec: &T,
    alias: &str,
) -> Result<()> {
    if rec.orig().is_empty() {
        let current = rec.name().get();
        tx.set_name(rec.orig(), &current)?;
        list::remember_alias::<T>(tx, off)?;
    }
    list::remove::<T>(tx, head, off)?;
    tx.set_name(rec.name(), alias)?;
    list::insert_sorted(tx, head, off, rec)
}

fn restore<T: Aliased>(tx: &mut Txn<'_>, head: &ObjList, off: u64, rec: &T) -> Result<()> {
    if rec.orig().is_empty() {
        return Err(HalError::NotFound {
            kind: "alias",
            name: rec.name().get(),
        });
    }
    let orig = rec.orig().get();
    list::forget_alias::<T>(tx, off)?;
    list::remove::<T>(tx, head, off)?;
    tx.set_name(rec.name(), &orig)?;
    tx.set_name(rec.orig(), "")?;
    list::insert_sorted(tx, head, off, rec)
}

fn kind_name(kind: AliasKind) -> &'static str {
    match kind {
        AliasKind::Pin => "pin",
        AliasKind::Param => "param",
    }
}

fn dup(kind: AliasKind, name: &str) -> HalError {
    HalError::Duplicate {
        kind: kind_name(kind),
        name: name.to_string(),
    }
}

fn missing(kind: AliasKind, name: &str) -> HalError {
    HalError::NotFound {
        kind: kind_name(kind),
        name: name.to_string(),
    }
}

/// The HAL library call a lock refusal names.
fn alias_op(kind: AliasKind) -> &'static str {
    match kind {
        AliasKind::Pin => "pin_alias",
        AliasKind::Param => "param_alias",
    }
}
