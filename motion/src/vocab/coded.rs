//! [`coded_enum!`]: a field-less enum whose values travel as numbers and
//! print as fixed texts, described once as `Variant = code => "text"`.

/// Declares a `Copy` enum from `Variant = code => "text"` lines, with:
/// * `ALL`, every value in declaration order;
/// * `code()` and `from_code()`, the number on the wire and back;
/// * `text()` and `Display`, the text used in messages.
macro_rules! coded_enum {
    (
        $(#[doc = $doc:literal])*
        pub enum $name:ident {
            $(
                $(#[doc = $vdoc:literal])*
                $variant:ident = $code:literal => $text:literal,
            )+
        }
    ) => {
        $(#[doc = $doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub enum $name {
            $(
                $(#[doc = $vdoc])*
                $variant,
            )+
        }

        impl $name {
            /// Every value, in declaration order.
            pub const ALL: [$name; [$($code),+].len()] = [$($name::$variant),+];

            /// The code on the wire.
            pub fn code(self) -> u64 {
                match self {
                    $($name::$variant => $code,)+
                }
            }

            /// The value with wire code `code`.
            pub fn from_code(code: u64) -> Option<$name> {
                match code {
                    $($code => Some($name::$variant),)+
                    _ => None,
                }
            }

            /// The text used in messages.
            pub fn text(self) -> &'static str {
                match self {
                    $($name::$variant => $text,)+
                }
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.text())
            }
        }
    };
}

pub(crate) use coded_enum;
