//! sim-torch: the simulated plasma torch of LinuxCNC's QtPlasmaC sim
//! configurations (see `hal_launcher::sim_torch`).

fn main() {
    hal_tools::conventions::user_program_main(
        "sim-torch",
        hal_launcher::sim_torch::USAGE,
        hal_launcher::sim_torch::main,
    )
}
