//! Commands from stdin, one `World::execute` each on a world of one copy,
//! as Python's `World.execute` runs them: every step simulated (no prefix
//! state kept), or with `STATES` prefix states. Prints each outcome's
//! effect and the bits of its terminal point, to compare builds; the
//! subject of `scripts/rollout-instructions.sh --one-copy`.
//!
//! ```sh
//! cargo run --release --example one_copy -- puck_rooms [STATES] < commands.txt
//! ```

use e3d::{Scene, World};
use std::io::BufRead;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scene = Scene::resolve(args.first().ok_or("usage: one_copy SCENE [STATES]")?)?;
    let mut world = scene.physics_world().ok_or("not a physics scene")?;
    world.set_prefix_states(args.get(1).map_or(Ok(0), |s| s.parse())?);
    let space = world.command_space().clone();
    for line in std::io::stdin().lock().lines() {
        let o = world.execute(&space.parse(line?.trim())?)?;
        println!(
            "{} {} {}",
            o.effect,
            o.point[0].to_bits(),
            o.point[1].to_bits()
        );
    }
    Ok(())
}
