//! linuxcnc-ethercat's `ethercat-conf.xml`, read as `lcec_conf` reads
//! it: `<masters>` holding `<master idx appTimePeriod refClockSyncCycles
//! name>`, each holding `<slave idx type name vid pid configPdos>` with
//! `<dcConf>`, `<watchdog>`, `<sdoConfig idx subIdx>` (with
//! `<sdoDataRaw data>`), `<syncManager idx dir>` / `<pdo idx>` /
//! `<pdoEntry idx subIdx bitLen halPin halType scale offset>` with
//! `<complexEntry>` bit fields, and `<modParam name value>`.
//!
//! Numbers in `idx`, `subIdx`, `vid`, `pid`, `assignActivate` are
//! hexadecimal with or without `0x`, as lcec reads them; times are
//! decimal; `sync0Cycle="*N"` is N application periods. Every error names
//! the file, the line and the element.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// A HAL pin type as `halType` names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HalType {
    /// `bit`.
    Bit,
    /// `s32`.
    S32,
    /// `u32`.
    U32,
    /// `float`: a signed integer on the wire, float in HAL.
    Float,
    /// `float-unsigned`.
    FloatUnsigned,
    /// `float-ieee`: a 32-bit IEEE float on the wire.
    FloatIeee,
    /// `float-double-ieee`: a 64-bit IEEE float on the wire.
    FloatDoubleIeee,
    /// `complex`: bit fields in `<complexEntry>`s.
    Complex,
}

impl HalType {
    fn parse(s: &str) -> Option<HalType> {
        Some(match s {
            "bit" => HalType::Bit,
            "s32" => HalType::S32,
            "u32" => HalType::U32,
            "float" => HalType::Float,
            "float-unsigned" => HalType::FloatUnsigned,
            "float-ieee" => HalType::FloatIeee,
            "float-double-ieee" => HalType::FloatDoubleIeee,
            "complex" => HalType::Complex,
            _ => return None,
        })
    }
}

/// A bit field of a complex entry.
#[derive(Debug, Clone, PartialEq)]
pub struct ComplexEntry {
    /// Bits.
    pub bit_len: u8,
    /// Pin name (None: padding).
    pub hal_pin: Option<String>,
    /// Pin type.
    pub hal_type: Option<HalType>,
    /// Scale.
    pub scale: f64,
    /// Offset.
    pub offset: f64,
}

/// A PDO entry.
#[derive(Debug, Clone, PartialEq)]
pub struct PdoEntry {
    /// Object index (0 for a gap).
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// Bits.
    pub bit_len: u8,
    /// Pin name.
    pub hal_pin: Option<String>,
    /// Pin type.
    pub hal_type: Option<HalType>,
    /// Scale.
    pub scale: f64,
    /// Offset.
    pub offset: f64,
    /// Bit fields (`halType="complex"`).
    pub complex: Vec<ComplexEntry>,
}

/// A PDO.
#[derive(Debug, Clone, PartialEq)]
pub struct Pdo {
    /// Index.
    pub index: u16,
    /// Entries.
    pub entries: Vec<PdoEntry>,
}

/// A sync manager.
#[derive(Debug, Clone, PartialEq)]
pub struct SyncManager {
    /// Index.
    pub index: u8,
    /// Outputs (`dir="out"`) or inputs.
    pub output: bool,
    /// PDOs.
    pub pdos: Vec<Pdo>,
}

/// A SYNC cycle: nanoseconds, or (`*N`) N application periods.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cycle {
    /// Nanoseconds.
    Ns(u64),
    /// Application periods.
    Periods(u64),
}

impl Cycle {
    /// The cycle in ns for an application period of `app_ns`.
    pub fn ns(self, app_ns: u64) -> u64 {
        match self {
            Cycle::Ns(n) => n,
            Cycle::Periods(k) => k.saturating_mul(app_ns),
        }
    }
}

/// `<dcConf>`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DcConf {
    /// AssignActivate word.
    pub assign_activate: u16,
    /// SYNC0 cycle.
    pub sync0_cycle: Cycle,
    /// SYNC0 shift (ns).
    pub sync0_shift: i64,
    /// SYNC1 cycle.
    pub sync1_cycle: Cycle,
    /// SYNC1 shift (ns).
    pub sync1_shift: i64,
}

/// `<sdoConfig>`: a write in PRE-OP.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SdoConfig {
    /// Index.
    pub index: u16,
    /// Sub-index; None for `subIdx="complete"`.
    pub sub: Option<u8>,
    /// The data.
    pub data: Vec<u8>,
}

/// A slave.
#[derive(Debug, Clone, PartialEq)]
pub struct Slave {
    /// Position.
    pub index: u16,
    /// Type (`generic`, `EL1008`, ...).
    pub kind: String,
    /// Name (pins are `lcec.<master>.<name>.<pin>`).
    pub name: String,
    /// Vendor id (generic).
    pub vid: Option<u32>,
    /// Product code (generic).
    pub pid: Option<u32>,
    /// `configPdos`.
    pub config_pdos: bool,
    /// Distributed clocks.
    pub dc: Option<DcConf>,
    /// Watchdog: divider and intervals.
    pub watchdog: Option<(u16, u16)>,
    /// SDO writes.
    pub sdos: Vec<SdoConfig>,
    /// Sync managers (generic).
    pub sync_managers: Vec<SyncManager>,
    /// `<modParam>`s.
    pub mod_params: Vec<(String, String)>,
    /// The line of `<slave>`, for later messages.
    pub line: u32,
}

/// A master.
#[derive(Debug, Clone, PartialEq)]
pub struct Master {
    /// Index.
    pub index: u32,
    /// Name (pins are `lcec.<name>.`; default the index).
    pub name: String,
    /// Application time period (ns).
    pub app_time_period: u64,
    /// Reference clock sync cycles: the application time goes to the
    /// reference clock every this many cycles (unless
    /// `sync_to_ref_clock`).
    pub ref_clock_sync_cycles: i32,
    /// `syncToRefClock`: the master's application time follows the
    /// reference clock (lcec's PLL) instead of the reference clock
    /// taking the application time. Without the attribute, a negative
    /// `refClockSyncCycles` asks for it (as lcec reads older files).
    pub sync_to_ref_clock: bool,
    /// Slaves.
    pub slaves: Vec<Slave>,
}

/// The whole configuration.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Config {
    /// Masters.
    pub masters: Vec<Master>,
}

struct Ctx<'a> {
    file: &'a Path,
    doc: &'a roxmltree::Document<'a>,
}

impl Ctx<'_> {
    fn err(&self, node: roxmltree::Node<'_, '_>, reason: impl Into<String>) -> Error {
        let line = self.doc.text_pos_at(node.range().start).row;
        Error::Config {
            file: self.file.to_path_buf(),
            line,
            element: node.tag_name().name().to_string(),
            reason: reason.into(),
        }
    }

    fn attr<'n>(&self, node: roxmltree::Node<'n, '_>, name: &str) -> Result<&'n str> {
        node.attribute(name)
            .ok_or_else(|| self.err(node, format!("attribute {name} is missing")))
    }

    fn hex(&self, node: roxmltree::Node<'_, '_>, name: &str) -> Result<u32> {
        let v = self.attr(node, name)?;
        parse_hex(v)
            .ok_or_else(|| self.err(node, format!("{name}=\"{v}\" is not a hexadecimal number")))
    }

    fn hex_or(&self, node: roxmltree::Node<'_, '_>, name: &str, default: u32) -> Result<u32> {
        match node.attribute(name) {
            Some(_) => self.hex(node, name),
            None => Ok(default),
        }
    }

    fn dec<T: std::str::FromStr>(
        &self,
        node: roxmltree::Node<'_, '_>,
        name: &str,
        default: Option<T>,
    ) -> Result<T> {
        match node.attribute(name) {
            Some(v) => v.trim().parse().map_err(|_| {
                self.err(
                    node,
                    format!("{name}=\"{v}\" is not a number of the right range"),
                )
            }),
            None => default.ok_or_else(|| self.err(node, format!("attribute {name} is missing"))),
        }
    }

    fn float(&self, node: roxmltree::Node<'_, '_>, name: &str, default: f64) -> Result<f64> {
        match node.attribute(name) {
            Some(v) => match v.trim().parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(self.err(node, format!("{name}=\"{v}\" is not a finite number"))),
            },
            None => Ok(default),
        }
    }

    fn fit<T: TryFrom<u32>>(&self, node: roxmltree::Node<'_, '_>, name: &str, v: u32) -> Result<T> {
        T::try_from(v).map_err(|_| self.err(node, format!("{name} {v:#x} is out of range")))
    }

    /// Only the elements allowed here; anything else is an error.
    fn children<'n>(
        &self,
        node: roxmltree::Node<'n, '_>,
        allowed: &[&str],
    ) -> Result<Vec<roxmltree::Node<'n, 'n>>>
    where
        'n: 'n,
    {
        let mut out = Vec::new();
        for c in node.children().filter(|c| c.is_element()) {
            if !allowed.contains(&c.tag_name().name()) {
                return Err(self.err(
                    c,
                    format!(
                        "not allowed in <{}> (allowed: {})",
                        node.tag_name().name(),
                        allowed.join(", ")
                    ),
                ));
            }
            out.push(c);
        }
        Ok(out)
    }
}

/// A hexadecimal number, with or without `0x`.
pub fn parse_hex(s: &str) -> Option<u32> {
    let t = s.trim();
    let t = t
        .strip_prefix("0x")
        .or_else(|| t.strip_prefix("0X"))
        .unwrap_or(t);
    if t.is_empty() {
        return None;
    }
    u32::from_str_radix(t, 16).ok()
}

/// Bytes a configuration file may have at most.
pub const MAX_FILE_BYTES: usize = 1 << 20;

/// Reads a configuration file's text (at most [`MAX_FILE_BYTES`]).
pub fn read_text(path: &Path) -> Result<String> {
    use std::io::Read;
    let read_err = |source| Error::ReadFile {
        path: path.to_path_buf(),
        source,
    };
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .map_err(read_err)?
        .take(MAX_FILE_BYTES as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(read_err)?;
    if bytes.len() > MAX_FILE_BYTES {
        return Err(Error::Config {
            file: path.to_path_buf(),
            line: 1,
            element: "xml".into(),
            reason: format!("larger than {MAX_FILE_BYTES} bytes"),
        });
    }
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// Reads a configuration file.
pub fn read(path: &Path) -> Result<Config> {
    parse(&read_text(path)?, path)
}

/// Parses configuration text; `file` names it in errors.
pub fn parse(text: &str, file: &Path) -> Result<Config> {
    let doc = roxmltree::Document::parse(text).map_err(|e| Error::Config {
        file: PathBuf::from(file),
        line: e.pos().row,
        element: "xml".into(),
        reason: e.to_string(),
    })?;
    let cx = Ctx { file, doc: &doc };
    let root = doc.root_element();
    if root.tag_name().name() != "masters" {
        return Err(cx.err(root, "the root element must be <masters>"));
    }
    let mut cfg = Config::default();
    for m in cx.children(root, &["master"])? {
        let index = cx.dec(m, "idx", Some(0u32))?;
        let mut master = Master {
            index,
            name: m
                .attribute("name")
                .map_or_else(|| index.to_string(), str::to_string),
            app_time_period: cx.dec(m, "appTimePeriod", None)?,
            ref_clock_sync_cycles: cx.dec(m, "refClockSyncCycles", None)?,
            sync_to_ref_clock: false,
            slaves: cx
                .children(m, &["slave"])?
                .into_iter()
                .map(|s| slave(&cx, s))
                .collect::<Result<_>>()?,
        };
        if master.app_time_period == 0 {
            return Err(cx.err(m, "appTimePeriod must be more than 0 ns"));
        }
        master.sync_to_ref_clock = match m.attribute("syncToRefClock").map(str::trim) {
            Some("true" | "1") => true,
            Some("false" | "0") => false,
            Some(v) => {
                return Err(cx.err(
                    m,
                    format!("syncToRefClock=\"{v}\" is neither true nor false"),
                ))
            }
            None => master.ref_clock_sync_cycles < 0,
        };
        if let Some(dup) = cfg
            .masters
            .iter()
            .find(|x| x.index == index || x.name == master.name)
        {
            return Err(cx.err(
                m,
                format!("master {} ({}) is configured twice", dup.index, dup.name),
            ));
        }
        check_slaves(&cx, m, &master)?;
        cfg.masters.push(master);
    }
    Ok(cfg)
}

fn check_slaves(cx: &Ctx<'_>, m: roxmltree::Node<'_, '_>, master: &Master) -> Result<()> {
    for (i, a) in master.slaves.iter().enumerate() {
        for b in &master.slaves[..i] {
            if a.index == b.index || a.name == b.name {
                let node = m.children().filter(|c| c.is_element()).nth(i).unwrap_or(m);
                return Err(cx.err(
                    node,
                    format!(
                        "slave idx {} / name {} repeats slave idx {} / name {}",
                        a.index, a.name, b.index, b.name
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn slave(cx: &Ctx<'_>, s: roxmltree::Node<'_, '_>) -> Result<Slave> {
    let index: u16 = cx.dec(s, "idx", None)?;
    let kind = cx.attr(s, "type")?.to_string();
    let generic = kind == "generic";
    let line = cx.doc.text_pos_at(s.range().start).row;
    let mut out = Slave {
        index,
        name: s
            .attribute("name")
            .map_or_else(|| index.to_string(), str::to_string),
        vid: None,
        pid: None,
        config_pdos: s.attribute("configPdos") == Some("true"),
        dc: None,
        watchdog: None,
        sdos: Vec::new(),
        sync_managers: Vec::new(),
        mod_params: Vec::new(),
        line,
        kind,
    };
    // A generic slave and a CiA 402 drive of lcec's basic_cia402 driver
    // say which device they are; typed terminals know it.
    if generic || out.kind == "basic_cia402" {
        out.vid = Some(cx.hex(s, "vid")?);
        out.pid = Some(cx.hex(s, "pid")?);
    } else if s.attribute("vid").is_some() || s.attribute("pid").is_some() {
        return Err(cx.err(
            s,
            "vid and pid are for type=\"generic\" and type=\"basic_cia402\" only",
        ));
    }
    if out.name.is_empty() || out.name.contains(char::is_whitespace) {
        return Err(cx.err(s, format!("name \"{}\" is not a HAL name part", out.name)));
    }
    let allowed: &[&str] = &[
        "dcConf",
        "watchdog",
        "sdoConfig",
        "idnConfig",
        "initCmds",
        "syncManager",
        "modParam",
    ];
    for c in cx.children(s, allowed)? {
        match c.tag_name().name() {
            "dcConf" => out.dc = Some(dc_conf(cx, c)?),
            "watchdog" => {
                out.watchdog = Some((cx.dec(c, "divider", None)?, cx.dec(c, "intervals", None)?))
            }
            "sdoConfig" => out.sdos.push(sdo_config(cx, c)?),
            "syncManager" => {
                if !generic {
                    return Err(cx.err(c, "syncManager is for type=\"generic\" only"));
                }
                out.sync_managers.push(sync_manager(cx, c)?);
            }
            "modParam" => out.mod_params.push((
                cx.attr(c, "name")?.to_string(),
                cx.attr(c, "value")?.to_string(),
            )),
            other => return Err(cx.err(c, format!("<{other}> is not supported by this master"))),
        }
    }
    Ok(out)
}

fn dc_conf(cx: &Ctx<'_>, c: roxmltree::Node<'_, '_>) -> Result<DcConf> {
    let cycle = |name: &str| -> Result<Cycle> {
        match c.attribute(name) {
            None => Ok(Cycle::Ns(0)),
            Some(v) => {
                let parsed = match v.trim().strip_prefix('*') {
                    Some(n) => n.parse::<u64>().map(Cycle::Periods),
                    None => v.trim().parse::<u64>().map(Cycle::Ns),
                };
                parsed
                    .map_err(|_| cx.err(c, format!("{name}=\"{v}\" is neither ns nor *N periods")))
            }
        }
    };
    Ok(DcConf {
        assign_activate: cx.fit(c, "assignActivate", cx.hex(c, "assignActivate")?)?,
        sync0_cycle: cycle("sync0Cycle")?,
        sync0_shift: cx.dec(c, "sync0Shift", Some(0))?,
        sync1_cycle: cycle("sync1Cycle")?,
        sync1_shift: cx.dec(c, "sync1Shift", Some(0))?,
    })
}

fn sdo_config(cx: &Ctx<'_>, c: roxmltree::Node<'_, '_>) -> Result<SdoConfig> {
    let index = cx.fit(c, "idx", cx.hex(c, "idx")?)?;
    let sub = match cx.attr(c, "subIdx")? {
        "complete" => None,
        _ => Some(cx.fit(c, "subIdx", cx.hex(c, "subIdx")?)?),
    };
    let mut data = Vec::new();
    for d in cx.children(c, &["sdoDataRaw"])? {
        let raw = cx.attr(d, "data")?;
        for word in raw.split_whitespace() {
            let b = u8::from_str_radix(word.trim_start_matches("0x"), 16)
                .map_err(|_| cx.err(d, format!("\"{word}\" in data is not a hexadecimal byte")))?;
            data.push(b);
        }
    }
    if data.is_empty() {
        return Err(cx.err(c, "no <sdoDataRaw data=\"..\"> bytes"));
    }
    Ok(SdoConfig { index, sub, data })
}

/// Sync managers a slave has at most (their PDO assignments are
/// 0x1C10..0x1C2F).
pub const MAX_SYNC_MANAGERS: u8 = 32;
/// PDOs per sync manager and entries per PDO at most (CoE's sub-indices
/// 1..254).
pub const MAX_PDO_ITEMS: usize = 254;

fn sync_manager(cx: &Ctx<'_>, c: roxmltree::Node<'_, '_>) -> Result<SyncManager> {
    let index: u8 = cx.dec(c, "idx", None)?;
    if index >= MAX_SYNC_MANAGERS {
        return Err(cx.err(c, format!("idx {index} is not a sync manager 0..31")));
    }
    let output = match cx.attr(c, "dir")? {
        "out" => true,
        "in" => false,
        d => return Err(cx.err(c, format!("dir=\"{d}\" is neither in nor out"))),
    };
    let mut pdos = Vec::new();
    for p in cx.children(c, &["pdo"])? {
        let mut entries = Vec::new();
        for e in cx.children(p, &["pdoEntry"])? {
            if entries.len() == MAX_PDO_ITEMS {
                return Err(cx.err(e, format!("more than {MAX_PDO_ITEMS} entries in one PDO")));
            }
            entries.push(pdo_entry(cx, e)?);
        }
        if pdos.len() == MAX_PDO_ITEMS {
            return Err(cx.err(
                p,
                format!("more than {MAX_PDO_ITEMS} PDOs in one sync manager"),
            ));
        }
        pdos.push(Pdo {
            index: cx.fit(p, "idx", cx.hex(p, "idx")?)?,
            entries,
        });
    }
    Ok(SyncManager {
        index,
        output,
        pdos,
    })
}

fn read_hal_type(cx: &Ctx<'_>, e: roxmltree::Node<'_, '_>) -> Result<Option<HalType>> {
    e.attribute("halType")
        .map(|t| HalType::parse(t).ok_or_else(|| cx.err(e, format!("halType=\"{t}\" is not bit, s32, u32, float, float-unsigned, float-ieee, float-double-ieee or complex"))))
        .transpose()
}

fn pdo_entry(cx: &Ctx<'_>, e: roxmltree::Node<'_, '_>) -> Result<PdoEntry> {
    let bit_len: u8 = cx.dec(e, "bitLen", None)?;
    if bit_len == 0 || bit_len > 64 {
        return Err(cx.err(e, format!("bitLen {bit_len} is not 1..64")));
    }
    let hal_type = read_hal_type(cx, e)?;
    let hal_pin = e.attribute("halPin").map(str::to_string);
    let mut complex = Vec::new();
    for c in cx.children(e, &["complexEntry"])? {
        let bits: u8 = cx.dec(c, "bitLen", None)?;
        complex.push(ComplexEntry {
            bit_len: bits,
            hal_pin: c.attribute("halPin").map(str::to_string),
            hal_type: read_hal_type(cx, c)?,
            scale: cx.float(c, "scale", 1.0)?,
            offset: cx.float(c, "offset", 0.0)?,
        });
    }
    match hal_type {
        Some(HalType::Complex) => {
            let total: u32 = complex.iter().map(|c| u32::from(c.bit_len)).sum();
            if total > u32::from(bit_len) {
                return Err(cx.err(
                    e,
                    format!("complexEntry bits add up to {total}, more than bitLen {bit_len}"),
                ));
            }
        }
        Some(_) if !complex.is_empty() => {
            return Err(cx.err(e, "complexEntry needs halType=\"complex\""))
        }
        Some(HalType::Bit) if bit_len != 1 && hal_pin.is_some() => {
            // lcec reads bit 0 of a wider entry; allowed.
        }
        _ => {}
    }
    if hal_pin.is_some() && hal_type.is_none() {
        return Err(cx.err(e, "halPin needs a halType"));
    }
    Ok(PdoEntry {
        index: cx.fit(e, "idx", cx.hex_or(e, "idx", 0)?)?,
        sub: cx.fit(e, "subIdx", cx.hex_or(e, "subIdx", 0)?)?,
        bit_len,
        hal_pin,
        hal_type,
        scale: cx.float(e, "scale", 1.0)?,
        offset: cx.float(e, "offset", 0.0)?,
        complex,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str = r#"<masters>
  <master idx="0" appTimePeriod="1000000" refClockSyncCycles="1000">
    <slave idx="0" type="EK1100" name="D0"/>
    <slave idx="1" type="EL1008" name="D1"/>
    <slave idx="2" type="generic" vid="00000002" pid="0x03fa3052" name="D2" configPdos="true">
      <dcConf assignActivate="300" sync0Cycle="*1" sync0Shift="0"/>
      <sdoConfig idx="8010" subIdx="01"><sdoDataRaw data="e8 03"/></sdoConfig>
      <syncManager idx="0" dir="in">
        <pdo idx="1a00">
          <pdoEntry idx="6000" subIdx="01" bitLen="1" halPin="din-0" halType="bit"/>
          <pdoEntry idx="6010" subIdx="00" bitLen="16" halType="complex">
            <complexEntry bitLen="1" halPin="ready" halType="bit"/>
            <complexEntry bitLen="7"/>
            <complexEntry bitLen="8" halPin="level" halType="float" scale="0.5"/>
          </pdoEntry>
        </pdo>
      </syncManager>
    </slave>
    <slave idx="3" type="EL7041" name="X"><modParam name="maxCurrent" value="1500"/></slave>
  </master>
</masters>"#;

    #[test]
    fn sample_parses() {
        let c = parse(SAMPLE, Path::new("ethercat-conf.xml")).unwrap();
        let m = &c.masters[0];
        assert_eq!(
            (m.name.as_str(), m.app_time_period, m.slaves.len()),
            ("0", 1_000_000, 4)
        );
        let g = &m.slaves[2];
        assert_eq!((g.vid, g.pid), (Some(2), Some(0x03FA_3052)));
        assert_eq!(
            g.sdos[0],
            SdoConfig {
                index: 0x8010,
                sub: Some(1),
                data: vec![0xE8, 3]
            }
        );
        assert_eq!(g.dc.unwrap().assign_activate, 0x300);
        assert_eq!(g.dc.unwrap().sync0_cycle, Cycle::Periods(1));
        let e = &g.sync_managers[0].pdos[0].entries;
        assert_eq!(e[0].hal_pin.as_deref(), Some("din-0"));
        assert_eq!(e[1].complex.len(), 3);
        assert_eq!(e[1].complex[2].scale, 0.5);
        assert_eq!(
            m.slaves[3].mod_params,
            vec![("maxCurrent".into(), "1500".into())]
        );
        assert_eq!(m.slaves[2].line, 5);
    }

    #[test]
    fn sync_to_ref_clock_from_the_attribute_or_a_negative_cycle_count() {
        let master = |attrs: &str| {
            let xml =
                format!("<masters><master idx=\"0\" appTimePeriod=\"1000000\" {attrs}/></masters>");
            parse(&xml, Path::new("t.xml")).map(|c| c.masters[0].sync_to_ref_clock)
        };
        assert!(!master(r#"refClockSyncCycles="1000""#).unwrap());
        assert!(master(r#"refClockSyncCycles="-1""#).unwrap());
        assert!(master(r#"refClockSyncCycles="1000" syncToRefClock="true""#).unwrap());
        assert!(!master(r#"refClockSyncCycles="-1" syncToRefClock="false""#).unwrap());
        let e = master(r#"refClockSyncCycles="1" syncToRefClock="yes""#)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("t.xml") && e.contains("syncToRefClock=\"yes\""),
            "{e}"
        );
    }

    #[test]
    fn errors_name_file_line_and_element() {
        let bad = SAMPLE.replace(
            "bitLen=\"16\" halType=\"complex\"",
            "bitLen=\"16\" halType=\"cplx\"",
        );
        let e = parse(&bad, Path::new("m.xml")).unwrap_err().to_string();
        assert!(
            e.starts_with("m.xml:11: <pdoEntry>: halType=\"cplx\""),
            "{e}"
        );
        let bad = SAMPLE.replace("pid=\"0x03fa3052\"", "pid=\"zz\"");
        let e = parse(&bad, Path::new("m.xml")).unwrap_err().to_string();
        assert!(e.starts_with("m.xml:5: <slave>: pid=\"zz\""), "{e}");
        let e = parse("<masters><master/></masters>", Path::new("m.xml"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("<master>: attribute appTimePeriod is missing"),
            "{e}"
        );
        let e = parse("<masters>", Path::new("m.xml"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("m.xml:1: <xml>:"), "{e}");
        let e = parse(&SAMPLE.replace("<modParam", "<bogus"), Path::new("m.xml"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("<bogus>: not allowed in <slave>"), "{e}");
        crate::fuzzing::xml(b"<masters><master appTimePeriod='1' refClockSyncCycles='-1'><slave idx='9' type='generic'/></master></masters>");
    }
}
