//! halui: LinuxCNC's HAL user interface, a client of the launcher's task
//! (see `hal_launcher::halui`).

fn main() {
    hal_tools::conventions::user_program_main(
        "halui",
        hal_launcher::halui::USAGE,
        hal_launcher::halui::main,
    )
}
