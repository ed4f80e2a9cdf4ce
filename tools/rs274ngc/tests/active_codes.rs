//! The interpreter's settings as LinuxCNC's stat reports them: feed,
//! speed and the two G64 tolerances.

use rs274ngc::{Config, Interp, PrintCanon, Status};

#[test]
fn g64_tolerances_are_in_the_active_codes() {
    let mut canon = PrintCanon::new(None, Vec::new());
    let mut interp = Interp::new(Config::default());
    interp.init(&mut canon).expect("init");
    interp
        .open_bytes(
            std::path::Path::new("g64.ngc"),
            b"G21 F300 S1200\nG64 P0.05 Q0.01\nM2\n".to_vec(),
            &mut canon,
        )
        .expect("open");
    // The two blocks before M2.
    for _ in 0..2 {
        assert_eq!(interp.read(&mut canon).expect("read"), Status::Ok);
        interp.execute(&mut canon).expect("execute");
    }
    let codes = interp.active_codes();
    assert!(
        (codes.tolerance - 0.05).abs() < 1e-12,
        "{}",
        codes.tolerance
    );
    assert!(
        (codes.naivecam_tolerance - 0.01).abs() < 1e-12,
        "{}",
        codes.naivecam_tolerance
    );
    assert!((codes.feed - 300.0).abs() < 1e-12, "{}", codes.feed);
    assert!((codes.speed - 1200.0).abs() < 1e-12, "{}", codes.speed);
}
