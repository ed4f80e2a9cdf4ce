//! The INI files halcmd reads for `[SECTION]KEY` substitution.

/// A parsed INI file: sections of `KEY = value` lines. The first value of a
/// repeated key wins, as in LinuxCNC.
#[derive(Debug, Clone, Default)]
pub struct Ini {
    entries: Vec<(String, String, String)>,
}

impl Ini {
    /// Parses INI text. `#` and `;` start comment lines.
    pub fn parse(text: &str) -> Ini {
        let mut ini = Ini::default();
        let mut section = String::new();
        for line in text.lines() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') || line.starts_with(';') {
                continue;
            }
            if let Some(rest) = line.strip_prefix('[') {
                if let Some(end) = rest.find(']') {
                    section = rest[..end].trim().to_string();
                }
                continue;
            }
            if let Some((k, v)) = line.split_once('=') {
                ini.entries
                    .push((section.clone(), k.trim().to_string(), v.trim().to_string()));
            }
        }
        ini
    }

    /// The value of `key` in `section`.
    pub fn get(&self, section: &str, key: &str) -> Option<&str> {
        self.entries
            .iter()
            .find(|(s, k, _)| s == section && k == key)
            .map(|(_, _, v)| v.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_value_wins_and_comments_are_skipped() {
        let ini = Ini::parse("# c\n[A]\nX = 1\n; c\nX = 2\n[B]\nX=3\n");
        assert_eq!(ini.get("A", "X"), Some("1"));
        assert_eq!(ini.get("B", "X"), Some("3"));
        assert_eq!(ini.get("C", "X"), None);
    }
}
