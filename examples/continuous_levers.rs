//! What would make arm7_continuous's rollouts cheaper, lever by lever
//! (docs/benchmarks.md, "Continuous commands"): `n` value vectors spread
//! over the ranges (a fixed generator), executed on a world of `copies`
//! copies (in batches of `copies`) with `iterations` solver iterations,
//! against one world of one copy with the scene's own settings. Prints
//! the rollouts per second and how many outcomes are the same bits, and
//! the same cell, as the single world's.
//!
//! ```sh
//! cargo run --release --example continuous_levers -- 8 4 512    # 8 copies, the scene's 4 iterations
//! cargo run --release --example continuous_levers -- 1 1 400    # one iteration
//! valgrind --tool=callgrind target/release/examples/continuous_levers 1 4 64 timed   # instructions of the timed part only: "timed" skips the reference
//! ```

use e3d::scene::WorldSpec;
use e3d::Scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: usize| args.get(i).map_or(Ok(default), |a| a.parse());
    let (copies, iterations, n) = (arg(0, 8)?, arg(1, 4)?, arg(2, 256)?);
    let timed_only = args.get(3).is_some_and(|a| a == "timed");
    let scene = Scene::builtin("arm7_continuous").ok_or("no arm7_continuous")?;
    let mut spec = scene.to_spec();
    if let WorldSpec::Physics(p) = &mut spec.world {
        p.solver_iterations = Some(iterations);
    }
    let lever = spec.validate()?;
    let space = scene.value_space().ok_or("not continuous")?;
    // a fixed linear congruential generator: the same vectors every run
    let mut x: u64 = 3;
    let mut unit = move || {
        x = x
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    let values: Vec<Vec<f64>> = (0..n)
        .map(|_| {
            (0..space.num_slots())
                .map(|s| {
                    let (lo, hi) = space.range(s);
                    lo + (hi - lo) * unit()
                })
                .collect()
        })
        .collect();
    let mut world = lever.as_physics().ok_or("not physics")?.world(copies);
    let start = std::time::Instant::now();
    let mut out = Vec::with_capacity(n);
    world.execute_values_batch(&values, &mut out);
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "{copies} copies, {iterations} iterations: {:.1} rollouts/s ({n} rollouts)",
        n as f64 / seconds
    );
    if timed_only {
        return Ok(());
    }
    let mut single = scene.physics_world().ok_or("not physics")?;
    let (mut bits, mut cells) = (0, 0);
    for (v, o) in values.iter().zip(&out) {
        let (want, got) = (
            single.execute_values(v)?,
            o.as_ref().map_err(|e| e.to_string())?,
        );
        bits += usize::from(want.point.map(f64::to_bits) == got.point.map(f64::to_bits));
        cells += usize::from(want.effect == got.effect);
    }
    println!("against one world of the scene: {bits} of {n} the same bits, {cells} the same cell");
    Ok(())
}
