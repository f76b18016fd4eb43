//! arm7 (docs/canonical-scenes.md, section 3): rest, replay, energy, the reward-cell rule,
//! and arm7 as a learning problem.

use e3d::learner::LearnerSetup;
use e3d::world::farthest_reached_cell;
use e3d::world::PhysicsWorld;
use e3d::{run_session, LearnerKind, OutcomeTable, Scene, SessionConfig, World};
use std::sync::OnceLock;

fn scene() -> Scene {
    Scene::load("scenes/arm7.ron").unwrap()
}

fn physics(scene: &Scene) -> PhysicsWorld {
    scene.physics_world().expect("arm7 is a physics scene")
}

/// All 2187 commands, executed once (in parallel) for the whole file.
fn table() -> &'static OutcomeTable {
    static TABLE: OnceLock<OutcomeTable> = OnceLock::new();
    TABLE.get_or_init(|| {
        let s = scene();
        OutcomeTable::build_parallel(|| s.build()).unwrap()
    })
}

#[test]
fn the_all_zero_command_leaves_the_tip_at_rest() {
    let s = scene();
    let mut w = physics(&s);
    let c = w.command_space().parse("0000000").unwrap();
    let o = w.execute(&c).unwrap();
    // no input, no gravity, no contact: nothing moves at all
    assert!(
        (o.point[0] - 1.75).abs() < 1e-5 && o.point[1].abs() < 1e-5,
        "{:?}",
        o.point
    );
    assert_eq!(o.effect, 7 * 15 + 14);
    // and no energy appears from nowhere
    let e = w.kinetic_energy_trace(&c).unwrap();
    assert_eq!(e.len(), 120);
    assert!(e.iter().all(|&k| k == 0.0), "{e:?}");
}

#[test]
fn once_the_push_ends_the_energy_never_exceeds_what_the_push_gave() {
    // After the push the only forces are joint damping (dissipative,
    // integrated implicitly), joint limits and contacts with restitution 0,
    // so the kinetic energy never exceeds its value at the end of the push
    // (step 15). Measured over all 2187 commands: at most 0.9967 times it.
    // It is not monotonic step by step: an impact takes most of the energy
    // in one step and the solver's position correction gives a little back
    // the next one (42 of the 2187 commands, one step each, at most
    // 0.0175 J, e.g. -0+++++ at step 77: 0.124 -> 0.037 -> 0.048 J); we
    // allow one such step per command.
    let s = scene();
    let mut w = physics(&s);
    let space = w.command_space().clone();
    let mut checked = 0;
    for i in (0..2187)
        .step_by(7)
        .chain([space.index_of(&space.parse("-0+++++").unwrap())])
    {
        let c = space.command_at(i);
        let e = w.kinetic_energy_trace(&c).unwrap();
        let pushed = e[14];
        for (k, &v) in e.iter().enumerate().skip(15) {
            assert!(
                v <= pushed * (1.0 + 1e-6) + 1e-12,
                "command {}: {v} J at step {} > {pushed} J at the end of the push",
                space.format(&c),
                k + 1
            );
        }
        let rebounds = e[14..]
            .windows(2)
            .filter(|w| w[1] - w[0] > 1e-9 + 1e-4 * w[0])
            .count();
        assert!(
            rebounds <= 1,
            "command {}: {rebounds} steps of growth",
            space.format(&c)
        );
        checked += 1;
    }
    assert_eq!(checked, 313 + 1);
}

#[test]
fn the_same_command_gives_the_same_bits_whatever_ran_before() {
    let s = scene();
    let mut w = physics(&s);
    let space = w.command_space().clone();
    let c = space.parse("-++++--").unwrap();
    let first = w.trace(&c).unwrap();
    for other in ["+++++++", "-0+-0+-", "+-+-+-+", "0000000"] {
        w.execute(&space.parse(other).unwrap()).unwrap();
    }
    let again = w.trace(&c).unwrap();
    assert_eq!(first, again);
    // bit for bit, not just equal as floats
    let bits = |t: &e3d::world::Trace| {
        t.points
            .iter()
            .flat_map(|p| [p[0].to_bits(), p[1].to_bits()])
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&first), bits(&again));
    // a fresh world agrees too, and so does the table built in parallel
    let fresh = physics(&s).trace(&c).unwrap();
    assert_eq!(bits(&first), bits(&fresh));
    assert_eq!(*table().lookup(&c).unwrap(), first.outcome);
}

#[test]
fn the_reward_cell_is_the_one_the_rule_picks() {
    let s = scene();
    let cell = farthest_reached_cell(table(), &s.effect_grid(), [1.75, 0.0]).unwrap();
    eprintln!("{cell:?}");
    assert_eq!(s.spec().reward.cells, vec![(cell.row, cell.col)]);
    // measured here: (6, 5), centre (-0.5, 0.25), behind the base, reached
    // by 5 commands, out of 68 reached cells
    assert_eq!((cell.row, cell.col), (6, 5));
    assert_eq!(cell.commands, 5);
    assert_eq!(cell.reached_cells, 68);
    let rewarded = table().outcomes().filter(|o| o.reward > 0.0).count();
    assert_eq!(rewarded, 5);
}

#[test]
fn arm7_reaches_many_cells_unevenly() {
    let counts = table().effect_counts();
    let mut reached: Vec<u64> = counts.iter().copied().filter(|&c| c > 0).collect();
    reached.sort_unstable_by(|a, b| b.cmp(a));
    let n = reached.len();
    eprintln!("{n} cells reached; counts {reached:?}");
    assert!((55..=90).contains(&n), "{n} cells reached");
    // uneven: the two most common cells take over 10% of the commands (an
    // even spread over the reached cells would give them 2/68 = 3%), and
    // many cells are reached by a handful of commands only
    let top2 = (reached[0] + reached[1]) as f64 / 2187.0;
    assert!(top2 > 0.10, "top two cells: {top2}");
    let rare = reached.iter().filter(|&&c| c <= 5).count();
    assert!(rare >= 10, "{rare} cells reached by at most 5 commands");
    // every command ran without blowing up (the table holds all 2187)
    assert_eq!(table().len(), 2187);
}

#[test]
fn e3d_spreads_arm7_effects_more_evenly_than_uniform() {
    // 5000 trials on the outcome table (bit-identical to the simulator).
    // Measured, normalised entropy over the cells reached, seeds 0-3:
    // E3D 0.926-0.937, uniform 0.872-0.876.
    let s = scene();
    let space = s.command_space();
    for seed in [0, 1] {
        let cfg = SessionConfig {
            trials: 5000,
            seed,
            use_reward: false,
        };
        let h = |kind: LearnerKind| {
            let mut l = LearnerSetup::new(kind).symbols(&space, 225).unwrap();
            let rec = run_session(&mut table(), &mut l, &cfg).unwrap();
            let counts = rec.effect_counts(0..cfg.trials);
            let reached = counts.iter().filter(|&&c| c > 0.0).count();
            e3d::effect::entropy(&counts) / (reached as f64).ln()
        };
        let (e, u) = (h(LearnerKind::E3d), h(LearnerKind::Uniform));
        eprintln!("seed {seed}: E3D {e:.4}, uniform {u:.4}");
        assert!(e > u + 0.03, "seed {seed}: E3D {e} vs uniform {u}");
    }
}

#[test]
fn arm7_curls_into_contacts_and_limits_well_below_the_speed_caps() {
    // Over all 2187 commands (`e3d scene stats arm7`): 44.2% bring two
    // non-neighbour links into contact, 24.1% press a joint against a
    // limit, the top angular speed is 11.7 rad/s (Rapier's cap: 47.1).
    // Here every 7th command.
    let s = scene();
    let mut w = physics(&s);
    let space = w.command_space().clone();
    let (mut n, mut contacts, mut limits, mut spin) = (0, 0, 0, 0.0f64);
    for i in (0..2187).step_by(7) {
        let st = w.inspect(&space.command_at(i)).unwrap();
        n += 1;
        contacts += usize::from(st.contact_steps > 0);
        limits += usize::from(st.limit_steps > 0);
        spin = spin.max(st.max_spin);
    }
    let (c, l) = (contacts as f64 / n as f64, limits as f64 / n as f64);
    eprintln!("{n} commands: contacts {c:.3}, limits {l:.3}, top spin {spin:.2} rad/s");
    assert!((0.30..0.60).contains(&c), "contacts {c}");
    assert!((0.12..0.40).contains(&l), "limits {l}");
    assert!(
        spin < 0.5 * std::f64::consts::FRAC_PI_4 * 60.0,
        "spin {spin}"
    );
    // the all-zero command touches nothing
    let zero = w.inspect(&space.parse("0000000").unwrap()).unwrap();
    assert_eq!(
        (zero.contact_steps, zero.limit_steps, zero.max_spin),
        (0, 0, 0.0)
    );
}

/// p*'s support on arm7 (docs/algorithms.md, "E3D"): 68 of its 225 cells
/// are reachable, so `OutcomeTable::reachable_target` raises `log p*` of a
/// reached cell by `log(225/68)`, and E3D's values, fed the same outcomes,
/// move by `log(225/68) / (beta lambda)` in the limit (0.399 at the paper's
/// task 2), `(1 - (1 - alpha lambda)^n)` of it after `n` updates.
#[test]
fn the_reachable_support_shifts_the_values_by_log_225_over_68() {
    use e3d::learner::E3d;
    use e3d::{Learner, Params, Target};
    let (s, table) = (scene(), table());
    let (all, reach) = (s.num_effects(), table.reachable_effects());
    assert_eq!((all, reach), (225, 68));
    let space = s.command_space();
    let p = Params::TASK2;
    let mut uniform = E3d::new(&space, all, &p, &Target::Uniform).unwrap();
    let mut on = E3d::new(&space, all, &p, &table.reachable_target()).unwrap();
    let mut n = vec![[0i32; 3]; space.num_slots()];
    // every command twice: each symbol of each slot 1458 times
    for t in 0..2 * 2187u64 {
        let cmd = space.command_at(t % 2187);
        let o = table.lookup(&cmd).unwrap();
        uniform.learn(&cmd, o);
        on.learn(&cmd, o);
        for (slot, &a) in cmd.symbols.iter().enumerate() {
            n[slot][a as usize] += 1;
        }
    }
    let shift = (225.0f64 / 68.0).ln() / (p.beta * p.lambda);
    assert!((shift - 0.39885).abs() < 1e-4, "{shift}");
    for (slot, counts) in n.iter().enumerate() {
        for (a, &k) in counts.iter().enumerate() {
            let expected = (1.0 - (1.0 - p.alpha * p.lambda).powi(k)) * shift;
            let d = on.q(slot)[a] - uniform.q(slot)[a];
            assert!(
                (d - expected).abs() < 1e-9,
                "slot {slot} symbol {a}: {d} against {expected}"
            );
        }
    }
    // each symbol chosen 1458 times: within 0.01% of the limit
    assert!(n.iter().flatten().all(|&k| k == 1458));
    assert!((on.q(0)[0] - uniform.q(0)[0] - shift).abs() < 1e-4 * shift);
}
