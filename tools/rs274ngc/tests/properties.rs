//! Properties: random programs, built from G-code's words and from raw
//! bytes, never make the interpreter panic or loop without end; devices
//! and oversized files are refused without being read into memory.

use proptest::prelude::*;

/// One word or construct of a G-code line.
fn word() -> impl Strategy<Value = String> {
    let letter = prop::sample::select(vec![
        'G', 'M', 'X', 'Y', 'Z', 'A', 'B', 'C', 'I', 'J', 'K', 'R', 'P', 'Q', 'L', 'F', 'S', 'T',
        'H', 'D', 'E', 'N', 'U', '@', '^', '$',
    ]);
    let number = prop_oneof![
        (-1000i32..1000).prop_map(|n| n.to_string()),
        (-100.0f64..100.0).prop_map(|x| format!("{x:.3}")),
        prop::sample::select(vec![
            "0", "1", "2", "3", "4", "17", "18", "19", "20", "21", "28", "30", "38.2", "40", "41",
            "42", "43", "49", "53", "54", "61", "64", "73", "80", "81", "83", "84", "87", "90",
            "91", "92", "93", "98", "99", "5.1",
        ])
        .prop_map(str::to_string),
    ];
    let expression = prop::sample::select(vec![
        "[1+2*3]",
        "[#1/0]",
        "[SIN[30]]",
        "[ATAN[1]/[0]]",
        "[2**10]",
        "[#<x>]",
        "[EXISTS[#<_y>]]",
        "[SQRT[-1]]",
        "[1 LT 2 AND 3]",
        "[[[[1]]]]",
        "[",
        "]",
        "[#5400]",
    ])
    .prop_map(str::to_string);
    prop_oneof![
        4 => (letter.clone(), number).prop_map(|(l, n)| format!("{l}{n}")),
        1 => (letter, expression).prop_map(|(l, e)| format!("{l}{e}")),
        1 => prop::sample::select(vec![
            "#1=5", "#<x>=#1", "#<_g>=[#<_x>+1]", "(MSG,hi)", "(DEBUG,#1)", "(PRINT,x)", "; c", "(open",
            "o100 sub", "o100 endsub", "o100 call [1]", "o<w> while [#1 LT 3]", "o<w> endwhile", "o1 if [1]",
            "o1 endif", "o2 do", "o2 while [0]", "o3 repeat [2]", "o3 endrepeat", "o4 break", "o100 return [2]",
            "%", "/", "M98 P100 L2", "M99", "O100",
        ])
        .prop_map(str::to_string),
    ]
}

fn program() -> impl Strategy<Value = Vec<u8>> {
    let line = prop::collection::vec(word(), 0..6).prop_map(|w| w.join(" "));
    prop::collection::vec(line, 0..40).prop_map(|lines| lines.join("\n").into_bytes())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn gcode_like_programs_never_panic(data in program()) {
        rs274ngc::fuzzing::program(&data);
    }

    #[test]
    fn arbitrary_bytes_never_panic(data in prop::collection::vec(any::<u8>(), 0..2000)) {
        rs274ngc::fuzzing::program(&data);
        rs274ngc::fuzzing::parameter_file(&data);
        rs274ngc::fuzzing::tool_table(&data);
    }

    #[test]
    fn refusal_lists_never_panic(data in program()) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.ngc");
        std::fs::write(&path, &data).unwrap();
        let list = rs274ngc::list_refusals_within(&path, rs274ngc::Config::default(), Vec::new(), 20_000);
        for pair in list.windows(2) {
            let key = |r: &rs274ngc::Refusal| (r.location.line, r.location.column);
            prop_assert!(key(&pair[0]) <= key(&pair[1]));
        }
        for r in &list {
            prop_assert!(r.location.line >= 1 && r.location.column >= 1, "{r}");
        }
    }
}

/// `rs274 -g /dev/zero` is refused at once, in the words of the suite's
/// reader of users' files.
#[test]
fn a_device_is_refused_as_not_a_regular_file() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rs274"))
        .args(["-g", "/dev/zero"])
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_ne!(out.status.code(), Some(0), "{err}");
    assert!(
        err.contains("is a character device, not a regular file"),
        "{err}"
    );
}
