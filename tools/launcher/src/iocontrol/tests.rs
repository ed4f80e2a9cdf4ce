//! iocontrol's handshakes, e-stop pulse and tool table writes.

use super::*;

const TABLE: &str = "T1 P5 D0.1\nT2 P3 D0.2\nT7 P0 ;spindle\n";

fn io(random: bool) -> IoControl {
    IoControl::new(
        ToolTable::parse(TABLE.as_bytes(), "t.tbl", random).unwrap(),
        None,
    )
}

fn inputs(prepared: bool, changed: bool) -> IoInputs {
    IoInputs {
        emc_enable_in: true,
        tool_prepared: prepared,
        tool_changed: changed,
        lube_level: true,
        v2: V2Inputs::default(),
    }
}

#[test]
fn g10_l1_sets_a_tool_and_writes_the_table_file() {
    let d = std::env::temp_dir().join(format!("iocontrol-g10-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let path = d.join("t.tbl");
    std::fs::write(&path, TABLE).unwrap();
    let table = ToolTable::load(&path, false).unwrap();
    let mut io = IoControl::new(table, Some(path.clone()));
    let mut entry = rs274ngc::ToolEntry::EMPTY;
    entry.toolno = 2;
    entry.offset.z = 12.5;
    entry.diameter = 6.0;
    io.request(&IoRequest::SetEntry { slot: 2, entry }).unwrap();
    let t = io.table().tool(2).unwrap();
    assert_eq!((t.number, t.offset[2], t.diameter), (2, 12.5, 6.0));
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("T2 P3 D6.000000 Z+12.500000"), "{text}");
    // An empty slot is refused; a table read incompletely is not
    // overwritten.
    assert_eq!(
        io.request(&IoRequest::SetEntry { slot: 40, entry }),
        Err(IoError::EmptySlot { slot: 40 })
    );
    io.hold_write_back();
    entry.offset.z = 1.0;
    io.request(&IoRequest::SetEntry { slot: 2, entry }).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn estop_reset_pulses_request_enable_for_one_cycle() {
    let mut io = io(false);
    io.request(&IoRequest::EstopOff).unwrap();
    assert!(io.outputs().user_enable_out && io.outputs().user_request_enable);
    io.step(&inputs(false, false));
    assert!(io.outputs().user_request_enable, "seen for one whole cycle");
    io.step(&inputs(false, false));
    assert!(!io.outputs().user_request_enable);
    assert!(io.outputs().user_enable_out);
    io.request(&IoRequest::Flood(true)).unwrap();
    io.request(&IoRequest::EstopOn).unwrap();
    assert_eq!(*io.outputs(), IoOutputs::default());
}

#[test]
fn non_random_prepare_and_change_handshakes() {
    let mut io = io(false);
    assert_eq!(io.tool_in_spindle(), 0);
    assert_eq!(
        io.request(&IoRequest::Prepare { tool: 2 }),
        Ok(Started::Waiting(Handshake::Prepare))
    );
    let o = *io.outputs();
    assert!(o.tool_prepare);
    assert_eq!(
        (o.tool_prep_number, o.tool_prep_pocket, o.tool_prep_index),
        (2, 3, 2)
    );
    assert!(io.step(&inputs(false, false)).is_empty());
    assert_eq!(
        io.step(&inputs(true, false)),
        [IoEvent::Prepared { tool: 2 }]
    );
    assert!(!io.outputs().tool_prepare);
    assert_eq!(
        io.request(&IoRequest::Load),
        Ok(Started::Waiting(Handshake::Change))
    );
    assert!(io.outputs().tool_change);
    assert_eq!(io.step(&inputs(true, true)), [IoEvent::Changed { tool: 2 }]);
    let o = *io.outputs();
    assert_eq!(
        (o.tool_number, o.tool_prep_number, o.tool_change),
        (2, 0, false)
    );
    assert_eq!(o.tool_from_pocket, 3, "tool 2 came from pocket 3");
    assert_eq!(
        io.table().tool(0).unwrap().number,
        2,
        "copied to the spindle slot"
    );
    // Loading the tool already in the spindle does nothing.
    io.request(&IoRequest::Prepare { tool: 2 }).unwrap();
    io.step(&inputs(true, false));
    assert_eq!(io.request(&IoRequest::Load), Ok(Started::Done));
    assert_eq!(io.prepared_tool(), Some(2), "still prepared, as LinuxCNC's");
    let o = *io.outputs();
    assert_eq!((o.tool_prep_number, o.tool_change), (2, false));
    // T0 M6 unloads.
    io.request(&IoRequest::Prepare { tool: 0 }).unwrap();
    assert_eq!(io.outputs().tool_prep_number, 0);
    assert_eq!(io.prepped_slot(), Some(0), "T0 counts as prepared at once");
    assert!(io.outputs().tool_prepare, "the handshake still runs");
    io.step(&inputs(true, false));
    io.request(&IoRequest::Load).unwrap();
    assert_eq!(io.step(&inputs(true, true)), [IoEvent::Changed { tool: 0 }]);
    assert!(io.table().tool(0).is_none());
}

#[test]
fn random_changer_with_an_empty_pocket_0_starts_with_tool_minus_1() {
    // LinuxCNC 2.9 (its io-startup test, random/no-tool-in-P0, run on
    // the 2.9 peer) reports -1 on tool-number and in stat.tool_in_spindle
    // when a random changer's table has nothing in pocket 0; a non-random
    // changer starts with 0 from the same table.
    let table = "T2 P2 D1.123 Z+2.0 ;\nT1 P1 D0.125 Z+1.0 ;\n";
    let random = ToolTable::parse(table.as_bytes(), "t.tbl", true).unwrap();
    let mut io = IoControl::new(random, None);
    assert_eq!(io.tool_in_spindle(), -1);
    assert_eq!(io.outputs().tool_number, -1);
    // T1 M6: the tool comes to the spindle, the empty entry goes to P1.
    io.request(&IoRequest::Prepare { tool: 1 }).unwrap();
    io.step(&inputs(true, false));
    io.request(&IoRequest::Load).unwrap();
    assert_eq!(io.step(&inputs(true, true)), [IoEvent::Changed { tool: 1 }]);
    assert_eq!((io.tool_in_spindle(), io.outputs().tool_number), (1, 1));
    assert!(io.table().tool(1).is_none(), "pocket 1 now holds nothing");

    let nonrandom = ToolTable::parse(table.as_bytes(), "t.tbl", false).unwrap();
    let io = IoControl::new(nonrandom, None);
    assert_eq!((io.tool_in_spindle(), io.outputs().tool_number), (0, 0));
}

#[test]
fn random_changer_swaps_pockets() {
    let mut io = io(true);
    assert_eq!(io.tool_in_spindle(), 7, "pocket 0 holds tool 7");
    io.request(&IoRequest::Prepare { tool: 1 }).unwrap();
    assert_eq!(io.outputs().tool_prep_pocket, 5);
    io.step(&inputs(true, false));
    io.request(&IoRequest::Load).unwrap();
    io.step(&inputs(true, true));
    assert_eq!(io.tool_in_spindle(), 1);
    assert_eq!(io.outputs().tool_from_pocket, 5);
    assert_eq!(io.table().tool(0).unwrap().number, 1);
    assert_eq!(
        io.table().tool(5).unwrap().number,
        7,
        "old tool went to pocket 5"
    );
    // The tool in the spindle needs no prepare handshake.
    assert_eq!(
        io.request(&IoRequest::Prepare { tool: 1 }),
        Ok(Started::Done)
    );
    assert_eq!(io.request(&IoRequest::Load), Ok(Started::Done));
}

#[test]
fn refusals_say_why() {
    let mut io = io(false);
    assert_eq!(
        io.request(&IoRequest::Prepare { tool: 9 }),
        Err(IoError::NoSuchTool { tool: 9 })
    );
    assert_eq!(io.request(&IoRequest::Load), Err(IoError::NothingPrepared));
    io.request(&IoRequest::Prepare { tool: 1 }).unwrap();
    assert_eq!(
        io.request(&IoRequest::Prepare { tool: 2 }),
        Err(IoError::Busy(Handshake::Prepare))
    );
    io.request(&IoRequest::Abort).unwrap();
    assert_eq!(io.busy(), None);
    io.request(&IoRequest::SetNumber { tool: 1 }).unwrap();
    assert_eq!(io.outputs().tool_number, 1);
}
