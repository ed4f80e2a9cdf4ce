//! The simulated board behaves as hardware.md §3 says, driven through
//! the register-level driver.

use std::sync::Arc;

use hal_driver::sim::SimBoard;

use super::*;
use crate::driver::Stg;

fn board(model: Model, dio: &str) -> (Arc<SimBoard<StgModel>>, Stg) {
    let (sim, drv) = crate::test_board::board(model, dio, None);
    drv.init();
    (sim, drv)
}

#[test]
fn dac_drives_the_motor_and_the_counter_counts_24_bits() {
    for model in [Model::One, Model::Two] {
        let (sim, drv) = board(model, "IIOO");
        assert_eq!(drv.latch_count(3), 0);
        drv.write_dac(3, regs::dac_code(2.0));
        sim.advance(500_000_000);
        // 2 V: (2 - 0.05) * 2 rev/s for 0.5 s less the 20 ms lag.
        let c = drv.latch_count(3);
        assert!((7_300..7_600).contains(&c), "{model}: {c}");
        assert_eq!(c, sim.with(|m| m.counter(3)));
        drv.write_dac(3, regs::dac_code(-5.0));
        sim.advance(500_000_000);
        let back = drv.latch_count(3);
        assert!(
            back > 0xF0_0000,
            "{model}: below zero wraps in 24 bits: {back:#x}"
        );
        assert_eq!(drv.latch_count(2), 0, "other channels stand still");
    }
}

#[test]
fn model2_index_latches_enabled_axes_only() {
    let (sim, drv) = board(Model::Two, "IIOO");
    sim.with(|m| m.turn_to(1, 0.5));
    drv.set_index_enables(0b0000_0010);
    sim.with(|m| {
        m.turn_to(0, 1.5); // channel 0 not enabled
        m.turn_to(1, 1.75); // index at 4000
    });
    assert_eq!(drv.index_flags(), 0b10);
    assert_eq!(drv.index_count(1), 4000, "OL loaded at the index");
    assert_eq!(drv.latch_count(1), 7000);
    sim.with(|m| m.turn_to(1, 2.25)); // another index while flagged
    assert_eq!(drv.index_count(1), 7000, "flag set: OL not reloaded");
    drv.clear_index_flags();
    assert_eq!(drv.index_flags(), 0);
    drv.set_index_enables(0);
    sim.with(|m| m.turn_to(1, 3.5));
    assert_eq!(drv.index_flags(), 0);
}

#[test]
fn model1_index_latches_the_selected_pair_and_clears_on_read() {
    let (sim, drv) = board(Model::One, "IIOO");
    sim.with(|m| {
        m.turn_to(4, 0.5);
        m.turn_to(5, 0.5);
    });
    drv.select_index_pair(2, true); // axes 4 and 5
    drv.clear_index_latches();
    assert_eq!(drv.irr() & (regs::IRR_LIXEVN | regs::IRR_LIXODD), 0);
    sim.with(|m| m.turn_to(5, 1.25)); // odd axis crosses its index
    let irr = drv.irr();
    assert_eq!(
        irr & (regs::IRR_LIXEVN | regs::IRR_LIXODD),
        regs::IRR_LIXODD
    );
    assert_eq!(drv.index_count(5), 4000);
    drv.clear_index_latches();
    assert_eq!(drv.irr() & regs::IRR_LIXODD, 0);
    // An index still active cannot be cleared; the live bit shows it.
    sim.with(|m| m.turn_to(4, 1.0));
    drv.clear_index_latches();
    let irr = drv.irr();
    assert_ne!(irr & regs::IRR_LIXEVN, 0);
    assert_ne!(irr & regs::IRR_IXEVN, 0);
    // Another pair's index is not seen.
    sim.with(|m| {
        m.turn_to(4, 1.5);
        m.turn_to(1, 2.0);
    });
    drv.clear_index_latches();
    assert_eq!(drv.irr() & (regs::IRR_LIXEVN | regs::IRR_LIXODD), 0);
    // Its polarity: with the level low, leaving the index is the edge.
    drv.select_index_pair(0, false);
    drv.clear_index_latches();
    assert_eq!(drv.irr() & regs::IRR_LIXODD, 0, "on the index: inactive");
    sim.with(|m| m.turn_to(1, 2.1));
    assert_ne!(
        drv.irr() & regs::IRR_LIXODD,
        0,
        "off the index the line is active"
    );
    assert_eq!(drv.index_count(1), 8400, "OL loaded leaving the index");
}

#[test]
fn adc_conversions_in_the_order_each_model_needs() {
    for model in [Model::One, Model::Two] {
        let (sim, drv) = board(model, "IIOO");
        for n in 0..8 {
            sim.with(|m| m.set_adc_volts(n, n as f64 - 3.5));
        }
        for n in [2usize, 7, 0] {
            drv.adc_start(n);
            assert!(!drv.adc_done(), "{model}: converting");
            sim.advance(ADC_NS_AUTOZERO);
            assert!(drv.adc_done(), "{model}: done");
            let want = ((n as f64 - 3.5) / regs::ADC_VOLTS_PER_COUNT).round() as i32;
            assert_eq!(drv.adc_result(n), want, "{model} channel {n}");
        }
    }
    // Model II keeps a result per channel; Model I has one result
    // register, whatever address reads it.
    let (sim, drv) = board(Model::Two, "IIOO");
    sim.with(|m| m.set_adc_volts(4, 1.0));
    drv.adc_start(4);
    sim.advance(ADC_NS_AUTOZERO);
    assert_eq!(drv.adc_result(5), 0);
    assert_eq!(drv.adc_result(4), 410);
    let (sim, drv) = board(Model::One, "IIOO");
    sim.with(|m| m.set_adc_volts(4, 1.0));
    drv.adc_start(4);
    sim.advance(ADC_NS_AUTOZERO);
    assert_eq!(drv.adc_result(5), 410);
}

#[test]
fn digital_ports_follow_dio_directions() {
    for (model, d_port) in [(Model::One, 0x401u16), (Model::Two, 0x405)] {
        let (sim, drv) = board(model, "IOIO");
        assert_eq!(sim.with(|m| m.port_output(0)), None);
        assert_eq!(sim.with(|m| m.port_output(1)), Some(0), "outputs start low");
        sim.with(|m| {
            m.set_port_lines(0, 0x5A);
            m.set_port_lines(2, 0x0F);
        });
        assert_eq!(drv.read_port(0), 0x5A);
        assert_eq!(drv.read_port(2), 0x0F);
        drv.write_port(1, 0xC3);
        drv.write_port(3, 0x81);
        assert_eq!(sim.with(|m| m.port_output(1)), Some(0xC3));
        assert_eq!(sim.with(|m| m.port_output(3)), Some(0x81));
        let log_port = sim.with(|m| m.port_output(3));
        assert_eq!(log_port, Some(0x81), "{model} port D at {d_port:#x}");
        let (sim, drv) = board(model, "OOOI");
        sim.with(|m| m.set_port_lines(3, 0x3C));
        assert_eq!(drv.read_port(3), 0x3C, "{model}: port D as input");
    }
}

#[test]
fn init_sets_each_models_own_registers() {
    let (sim, _) = board(Model::One, "IIOO");
    sim.with(|m| {
        assert_eq!(m.intc(), regs::INTC_AUTOZERO | regs::IRQ5);
        assert_eq!(m.pic_mask(), 0xFF);
        assert_eq!(
            (0..8).map(|n| m.dac_word(n)).collect::<Vec<_>>(),
            [0x1000; 8]
        );
    });
    let (sim, _) = board(Model::Two, "IIOO");
    sim.with(|m| {
        assert_eq!(m.cntrl0(), 0x8C);
        assert_eq!(m.cntrl1(), 0xFF);
        assert_eq!(m.index_registers(), (0, 0));
    });
}

#[test]
fn nothing_outside_the_windows_decodes() {
    let sim = SimBoard::new(StgModel::new(Model::Two, 0x300));
    use hal_driver::bus::PortBus;
    assert_eq!(sim.inb(0x320), 0xFF);
    assert_eq!(sim.inb(0x6FF), 0xFF);
    assert_eq!(sim.inw(0x31F), 0xFFFF, "a word running past the window");
    sim.outb(0x80, 1);
    assert_eq!(sim.with(|m| m.stray_accesses()), 4);
    assert_ne!(sim.inb(0x703), 0xFF, "BRDTST answers");
}
