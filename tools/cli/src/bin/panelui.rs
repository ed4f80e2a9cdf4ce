//! panelui: LinuxCNC's operator panel, a key matrix read from a sampler
//! into button pins and task commands (see `hal_launcher::panelui`).

fn main() {
    hal_tools::conventions::user_program_main(
        "panelui",
        hal_launcher::panelui::USAGE,
        hal_launcher::panelui::main,
    )
}
