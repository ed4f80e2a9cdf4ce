//! How each module is loaded for its man page when a plain `loadrt NAME`
//! does not do: what must come first, the arguments, and a note for the
//! page (a simulated backend, say).

/// A module's example load.
#[derive(Debug, Clone, Copy)]
pub struct Example {
    /// HAL lines run before the load (a kinematics module before motmod).
    pub before: &'static str,
    /// The arguments of `loadrt NAME ...`.
    pub args: &'static str,
    /// Said on the page about the example, if anything.
    pub note: &'static str,
    /// The load is served by a simulated Ethernet board of this preset:
    /// the test appends `board_ip=` with the simulator's address.
    pub eth_board: Option<&'static str>,
    /// The load fails by design (LinuxCNC's hm2_test): the page says why
    /// in its note, and the test checks that it fails and adds nothing.
    pub fails: bool,
}

/// Modules whose page is written by hand (it says more than a generated
/// one could); the test still checks that it names everything the
/// module exports and every parameter (`nameN` stands for `name1`,
/// `name2`, ...).
pub const HAND_WRITTEN: &[&str] = &["threads"];

const PLAIN: Example = Example {
    before: "",
    args: "",
    note: "",
    eth_board: None,
    fails: false,
};

/// The example load of `module`.
pub fn example_for(module: &str) -> Example {
    EXAMPLES
        .iter()
        .find(|(m, _)| *m == module)
        .map_or(PLAIN, |(_, e)| *e)
}

/// An example load with arguments only.
const fn args(args: &'static str) -> Example {
    Example { args, ..PLAIN }
}

/// An example load of a driver on its simulated backend.
const fn sim(args: &'static str, note: &'static str) -> Example {
    Example {
        args,
        note,
        ..PLAIN
    }
}

const HM2_CORE: &str = "loadrt hostmot2";

const EXAMPLES: &[(&str, Example)] = &[
    ("bldc", args("cfg=qi6")),
    ("debounce", args("cfg=2")),
    ("demux_generic", args("config=bf8")),
    ("enum", args("enums=D;stop;run;;fault")),
    ("gantry", args("personality=2")),
    ("matrix_kb", args("config=4x3s")),
    ("message", args("messages=\"Oil low\"")),
    ("mux_generic", args("config=ff4")),
    ("pwmgen", args("output_type=0")),
    ("sampler", args("cfg=fbs depth=1024")),
    ("stepgen", args("step_type=0")),
    ("streamer", args("cfg=fbs depth=1024")),
    ("watchdog", args("num_inputs=2")),
    ("weighted_sum", args("wsum_sizes=4")),
    (
        "motmod",
        Example {
            before: "loadrt trivkins",
            ..PLAIN
        },
    ),
    (
        "ads1115",
        sim("backend=sim", "The example uses a simulated chip; dev (the default) opens /dev/i2c-1."),
    ),
    (
        "mcp23017",
        sim("backend=sim", "The example uses a simulated chip; dev (the default) opens /dev/i2c-1."),
    ),
    (
        "pca9685",
        sim("backend=sim", "The example uses a simulated chip; dev (the default) opens /dev/i2c-1."),
    ),
    (
        "canservo",
        sim(
            "nodes=1 backend=sim",
            "The example uses a simulated drive; socketcan (the default) talks to can0.",
        ),
    ),
    (
        "lcec",
        sim(
            "config=../../configs/sim/ethercat-conf.xml backend=sim",
            "The example runs the suite's simulated EtherCAT segment of \
             configs/sim/ethercat-conf.xml; raw (the default) opens the \
             interfaces the file names.",
        ),
    ),
    (
        "hal_gpio",
        sim(
            "inputs=A outputs=B backend=sim",
            "The example uses the simulated chip; cdev (the default) opens /dev/gpiochip*.",
        ),
    ),
    (
        "hal_parport",
        sim(
            "cfg=\"0x378 sim\"",
            "The example uses a simulated port; ppdev and raw reach real ones.",
        ),
    ),
    (
        "hal_speaker",
        sim(
            "backend=sim",
            "The example uses the simulated speaker; auto (the default) takes port 0x61 \
             through ioperm when it is permitted, and the simulator otherwise.",
        ),
    ),
    (
        "hal_stg",
        sim(
            "backend=sim",
            "The example uses a simulated Model II card; ioperm (the default) needs port I/O.",
        ),
    ),
    (
        "hal_ppmc",
        sim(
            "sim=ppmc",
            "The example uses a simulated PPMC set (encoder, DAC and digital I/O boards); \
             without sim= the driver scans the EPP port at port_addr (default 0x378).",
        ),
    ),
    (
        "hal_motenc",
        sim(
            "backend=sim",
            "The example uses a simulated MOTENC-100; pci (the default) uses every card on the bus.",
        ),
    ),
    (
        "hm2_pci",
        Example {
            before: HM2_CORE,
            args: "sim=5i25",
            note: "The example uses a simulated 5I25; without sim= the module drives every \
                   Mesa PCI card it finds.",
            ..PLAIN
        },
    ),
    (
        "hm2_eth",
        Example {
            before: HM2_CORE,
            args: "",
            note: "The example talks to a simulated 7I96S (the board hm2-eth-sim(1) \
                   serves) on this machine; give board_ip= the address of a real board, \
                   or sim=7i96s (7i76e, 7i93, 7i92, 7i95) for the same board inside the \
                   HAL process, with no network.",
            eth_board: Some("7i96s"),
            fails: false,
        },
    ),
    (
        "hm2_7i43",
        Example {
            before: HM2_CORE,
            args: "sim=7i43",
            note: "The example uses a simulated 7I43 behind a simulated parallel port; \
                   without sim= the module drives the 7I43 on the port at ioaddr= \
                   (0x378) with raw port I/O.",
            ..PLAIN
        },
    ),
    (
        "hm2_7i90",
        Example {
            before: HM2_CORE,
            args: "sim=7i90",
            note: "The example uses a simulated 7I90 behind a simulated parallel port; \
                   without sim= the module drives the 7I90 on the port at ioaddr= \
                   (0x378) with raw port I/O.",
            ..PLAIN
        },
    ),
    (
        "hm2_spi",
        Example {
            before: HM2_CORE,
            args: "sim=7i90",
            note: "The example uses a simulated 7I90 behind a simulated SPI link; \
                   without sim= the module drives the board on spidev_path= \
                   (/dev/spidev1.0).",
            ..PLAIN
        },
    ),
    (
        "hm2_rpspi",
        Example {
            before: HM2_CORE,
            args: "sim=7c80",
            note: "The example uses a simulated 7C80 behind a simulated SPI link; \
                   without sim= the module drives the boards at the places spi_probe= \
                   names (/dev/spidev0.0 for SPI0/CE0).",
            ..PLAIN
        },
    ),
    (
        "setsserial",
        Example {
            before: "loadrt hostmot2\nloadrt hm2_pci sim=5i25-7i77",
            args: "cmd=\"set hm2_5i25.0.7i77.0.0.nvwatchdogtimeout 50\"",
            note: "setsserial acts once at load on a remote of a board a hostmot2 driver \
                   loaded (here the simulated 7I77 of a simulated 5I25): \
                   cmd=\"set <remote>.<parameter> <value>\" writes the parameter into the \
                   remote's EEPROM (decimal or 0x hex; the remote named as the driver names \
                   it, by board, port and channel or by unit number), \
                   cmd=\"flash <remote> <file>.BIN\" writes a remote firmware file from \
                   firmware_dir= (/lib/firmware) into its flash and needs hostmot2 loaded \
                   with sserial_baudrate=115200 (setup mode) and Smart Serial firmware \
                   version 34 (37 for an 8I20). LinuxCNC's setsserial always fails to load, \
                   so that it never stays loaded; this one succeeds when the command did and \
                   fails naming the step that went wrong otherwise, so a script can tell. \
                   Either way it makes no component, pin, function or thread and holds \
                   nothing; the host still lists the module after a success, so run \
                   unloadrt setsserial before the next command.",
            ..PLAIN
        },
    ),
    (
        "hm2_modbus",
        Example {
            before: "loadrt hostmot2\nloadrt hm2_pci sim=5i25-pktuart",
            args: "ports=hm2_5i25.0.pktuart.0 mbccbs=../../drivers/hostmot2/tests/data/sample.mbccb",
            note: "hm2_modbus runs Modbus RTU over a PktUART of a board a hostmot2 driver \
                   loaded (here PktUART 0 of a simulated 5I25), one instance per port in \
                   ports=, each running the compiled command file (.mbccb, written by \
                   LinuxCNC's mesambccc) at the same place in mbccbs=. Besides the \
                   instance's pins and parameters, each command of the file makes \
                   command.MM pins and the file names its data pins. Add \
                   hm2_modbus.N.process after the board's read and before its write: \
                   its PktUART's status words, received frames and writes travel in \
                   those two functions' bursts (no register access of its own, so no \
                   extra round trip on hm2_eth), and a reply reaches the pins two \
                   periods after the status shows it. A failed exchange counts on the command's errors pin and sets fault; \
                   the fifth in a row disables the command until reset rises; read pins \
                   keep their last good value.",
            ..PLAIN
        },
    ),
    (
        "hm2_test",
        Example {
            before: HM2_CORE,
            args: "test_pattern=0",
            note: "Every test pattern is a broken firmware image: the load fails with the \
                   message LinuxCNC gives for it and exports nothing, which is the test.",
            eth_board: None,
            fails: true,
        },
    ),
];
