//! classicladder: loads a ClassicLadder project into classicladder_rt
//! (see `hal_ladder::user`).

fn main() {
    hal_tools::conventions::user_program_main(
        "classicladder",
        hal_ladder::user::USAGE,
        hal_ladder::user::main,
    )
}
