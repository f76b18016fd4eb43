//! A tight loop of E3D trials on two_rooms (propose, table look-up, learn),
//! for timings and instruction counts without a benchmark harness.
//!
//! ```sh
//! cargo run --release --example trial_loop -- 5000000 concrete 7   # best of 7 runs, ns per trial
//! scripts/trial-instructions.sh                                    # instructions per trial (callgrind)
//! ```
//!
//! Arguments: trials (default 5 000 000), `concrete` (the `E3d` type, the
//! default), `dyn` (a `Box<dyn Learner>`) or `two` (two independent
//! sessions, their trials interleaved: the time per trial shows whether
//! one session's trials could overlap with another's), runs (default 1).
//! The check value is a sum of the effects: the same for the same code and
//! seed.
use e3d::learner::E3d;
use e3d::learner::LearnerSetup;
use e3d::{Learner, LearnerKind, OutcomeTable, Params, Scene, SessionRng, Target};
use rand::SeedableRng;
use std::hint::black_box;
use std::time::Instant;

fn run<L: Learner + ?Sized>(
    l: &mut L,
    table: &OutcomeTable,
    rng: &mut SessionRng,
    cmd: &mut e3d::Command,
    n: usize,
) -> usize {
    let mut acc = 0usize;
    for _ in 0..n {
        l.propose(rng, cmd);
        let o = *table.lookup(cmd).unwrap();
        l.learn(cmd, &o);
        acc = acc.wrapping_add(black_box(o.effect));
    }
    acc
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(5_000_000);
    let mode = args.get(2).cloned().unwrap_or("concrete".into());
    let runs: usize = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(1);
    let scene = Scene::builtin("two_rooms").unwrap();
    let table = OutcomeTable::build(&mut scene.build()).unwrap();
    let space = scene.command_space();
    let mut best = f64::INFINITY;
    let mut check = 0;
    for _ in 0..runs {
        let mut rng = SessionRng::seed_from_u64(1);
        let mut cmd = space.first();
        let t = Instant::now();
        let acc = if mode == "two" {
            let mut a = E3d::new(&space, 18, &Params::TASK2, &Target::Uniform).unwrap();
            let mut b = a.clone();
            let mut rng_b = SessionRng::seed_from_u64(2);
            let mut cmd_b = space.first();
            let mut acc = 0usize;
            for _ in 0..n / 2 {
                a.propose(&mut rng, &mut cmd);
                b.propose(&mut rng_b, &mut cmd_b);
                let (oa, ob) = (*table.lookup(&cmd).unwrap(), *table.lookup(&cmd_b).unwrap());
                a.learn(&cmd, &oa);
                b.learn(&cmd_b, &ob);
                acc = acc.wrapping_add(black_box(oa.effect) + black_box(ob.effect));
            }
            acc
        } else if mode == "dyn" {
            let mut l = LearnerSetup::new(LearnerKind::E3d)
                .params(Params::TASK2)
                .symbols(&space, 18)
                .unwrap();
            run(&mut l, &table, &mut rng, &mut cmd, n)
        } else {
            let mut l = E3d::new(&space, 18, &Params::TASK2, &Target::Uniform).unwrap();
            run(&mut l, &table, &mut rng, &mut cmd, n)
        };
        let dt = t.elapsed().as_secs_f64() / n as f64 * 1e9;
        best = best.min(dt);
        check = acc;
    }
    println!("{mode}: best {best:.2} ns/trial over {runs} runs (check {check})");
}
