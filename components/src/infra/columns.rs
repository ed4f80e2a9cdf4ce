//! The column types of sampler and streamer channels (`cfg=` strings).

use hal_core::{HalError, HalType};

/// Most columns one channel may have.
pub const MAX_COLUMNS: usize = 21;
/// Most channels one sampler or streamer may have.
pub const MAX_CHANNELS: usize = 8;

/// Module parameters of sampler and streamer.
pub const PARAMS: &[hal_core::ParamDecl] = &[
    hal_core::ParamDecl {
        name: "cfg",
        kind: hal_core::ParamKind::StrArray(MAX_CHANNELS),
        help: "column types per channel",
    },
    hal_core::ParamDecl {
        name: "depth",
        kind: hal_core::ParamKind::IntArray(MAX_CHANNELS),
        help: "FIFO depth per channel",
    },
];

/// Parses a cfg string: one letter per column.
pub fn parse_cfg(module: &str, cfg: &str) -> Result<Vec<HalType>, HalError> {
    if cfg.len() > MAX_COLUMNS {
        return Err(HalError::ModuleParam {
            module: module.to_string(),
            param: "cfg".into(),
            reason: format!("'{cfg}' has more than {MAX_COLUMNS} columns"),
        });
    }
    cfg.chars()
        .map(|c| {
            Ok(match c {
                'f' | 'F' | 'r' | 'R' => HalType::Float,
                'b' | 'B' => HalType::Bit,
                's' | 'S' => HalType::S32,
                'u' | 'U' => HalType::U32,
                'l' | 'L' => HalType::S64,
                'k' | 'K' => HalType::U64,
                _ => {
                    return Err(HalError::ModuleParam {
                        module: module.to_string(),
                        param: "cfg".into(),
                        reason: format!("invalid type character '{c}' in '{cfg}'"),
                    })
                }
            })
        })
        .collect()
}

/// The channels a `cfg=`/`depth=` pair describes: scanning stops at the
/// first empty cfg or non-positive depth.
pub fn channels(
    module: &str,
    cfgs: &[String],
    depths: &[i64],
) -> Result<Vec<(Vec<HalType>, usize)>, HalError> {
    let mut out = Vec::new();
    for n in 0..MAX_CHANNELS {
        let (Some(cfg), Some(&depth)) = (cfgs.get(n), depths.get(n)) else {
            break;
        };
        if cfg.is_empty() || depth <= 0 {
            break;
        }
        out.push((parse_cfg(module, cfg)?, depth as usize));
    }
    if out.is_empty() {
        return Err(HalError::ModuleLoad {
            module: module.to_string(),
            reason: "no channels specified".into(),
        });
    }
    Ok(out)
}

/// Name of the FIFO region of channel `n` of `module`.
pub fn fifo_name(module: &str, n: usize) -> String {
    format!("{module}.{n}.fifo")
}

/// Name of the pin of column `m` of channel `n` of `module`.
pub fn pin_name(module: &str, n: usize, m: usize) -> String {
    format!("{module}.{n}.pin.{m}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cfg_letters() {
        assert_eq!(
            parse_cfg("sampler", "fFrRbBsSuUlLkK").unwrap(),
            [
                HalType::Float,
                HalType::Float,
                HalType::Float,
                HalType::Float,
                HalType::Bit,
                HalType::Bit,
                HalType::S32,
                HalType::S32,
                HalType::U32,
                HalType::U32,
                HalType::S64,
                HalType::S64,
                HalType::U64,
                HalType::U64
            ]
        );
        assert!(parse_cfg("sampler", "fx").is_err());
        assert!(parse_cfg("sampler", &"f".repeat(22)).is_err());
    }

    #[test]
    fn channel_scan_stops_at_the_first_gap() {
        let cfgs = [
            "ff".to_string(),
            "b".to_string(),
            String::new(),
            "s".to_string(),
        ];
        let ch = channels("s", &cfgs, &[10, 5, 5, 5]).unwrap();
        assert_eq!(ch.len(), 2);
        let ch = channels("s", &cfgs, &[10, 0, 5]).unwrap();
        assert_eq!(ch.len(), 1);
        assert!(channels("s", &[], &[]).is_err());
    }
}
