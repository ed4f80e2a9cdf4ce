//! z_level_compensation: LinuxCNC's Z level compensation user component
//! (see `hal_launcher::zlevel`).

fn main() {
    hal_tools::conventions::user_program_main(
        "z_level_compensation",
        hal_launcher::zlevel::USAGE,
        hal_launcher::zlevel::main,
    )
}
