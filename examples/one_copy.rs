//! Commands from stdin, one `World::execute` each on a world of one copy,
//! as Python's `World.execute` runs them: every step simulated (no prefix
//! state kept), or with `STATES` prefix states. Prints each outcome's
//! effect and the bits of its terminal point, to compare builds; the
//! subject of `scripts/rollout-instructions.sh --one-copy`. With
//! `--random N`, runs N commands drawn from the scene's command space
//! (a fixed sequence, repeats possible) instead of reading stdin, and
//! prints each command too.
//!
//! ```sh
//! cargo run --release --example one_copy -- puck_rooms [STATES] < commands.txt
//! cargo run --release --example one_copy -- arm7 0 --random 500
//! ```

use e3d::{Scene, World};
use std::io::BufRead;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: one_copy SCENE [STATES] [--random N]";
    let scene = Scene::resolve(args.first().ok_or(usage)?)?;
    let mut world = scene.physics_world().ok_or("not a physics scene")?;
    world.set_prefix_states(args.get(1).map_or(Ok(0), |s| s.parse())?);
    let space = world.command_space().clone();
    let print = |o: e3d::Outcome| {
        println!(
            "{} {} {}",
            o.effect,
            o.point[0].to_bits(),
            o.point[1].to_bits()
        )
    };
    if args.get(2).map(String::as_str) == Some("--random") {
        let n: u64 = args.get(3).ok_or(usage)?.parse()?;
        let total = space.num_commands().ok_or("too many commands to index")?;
        // the SplitMix64 sequence seeded with its own increment: the same
        // commands on every build
        const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;
        for k in 1..=n {
            let draw = e3d::hash::splitmix64(GOLDEN.wrapping_mul(k));
            let command = space.command_at(draw % total);
            print!("{} ", space.format(&command));
            print(world.execute(&command)?);
        }
        return Ok(());
    }
    for line in std::io::stdin().lock().lines() {
        print(world.execute(&space.parse(line?.trim())?)?);
    }
    Ok(())
}
