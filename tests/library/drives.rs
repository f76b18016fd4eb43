//! The drives beyond the paper (docs/algorithms.md): RelaxedE3d does not
//! lock where E3D does, and keeps E3D's strength; the count bonus and
//! state marginal matching explore better than the uniform policy. Fixed
//! seeds; the thresholds leave room around the figures measured.

use e3d::learner::LearnerSetup;
use e3d::learner::{CountBonus, RelaxedE3d, StateMarginalMatching};
use e3d::{
    run_session, Command, Learner, LearnerKind, Outcome, OutcomeTable, Params, Scene,
    SessionConfig, Target,
};
use rayon::prelude::*;
use std::sync::OnceLock;

fn two_rooms() -> &'static (Scene, OutcomeTable) {
    static T: OnceLock<(Scene, OutcomeTable)> = OnceLock::new();
    T.get_or_init(|| {
        let scene = Scene::builtin("two_rooms").unwrap();
        let table = OutcomeTable::build(&mut *scene.build()).unwrap();
        (scene, table)
    })
}

/// Per session of `kind` over `seeds`: (normalised entropy, cumulative
/// reward, whether a reward was ever received).
fn sessions(kind: LearnerKind, task2: bool, seeds: std::ops::Range<u64>) -> Vec<(f64, f64, bool)> {
    let (scene, table) = two_rooms();
    let params = if task2 { Params::TASK2 } else { Params::TASK1 };
    seeds
        .into_par_iter()
        .map(|seed| {
            let mut l = LearnerSetup::new(kind)
                .params(params)
                .symbols(&scene.command_space(), scene.num_effects())
                .unwrap();
            let cfg = SessionConfig {
                trials: 5000,
                seed,
                use_reward: task2,
            };
            let m = run_session(&mut &*table, &mut l, &cfg)
                .unwrap()
                .metrics(&Target::Uniform);
            (
                m.normalized_entropy,
                m.cumulative_reward,
                m.first_reward_trial.is_some(),
            )
        })
        .collect()
}

fn mean(v: &[(f64, f64, bool)], f: impl Fn(&(f64, f64, bool)) -> f64) -> f64 {
    v.iter().map(f).sum::<f64>() / v.len() as f64
}

#[test]
fn relaxed_e3d_does_not_lock_where_e3d_does() {
    // task 2, seeds 0..1000: E3D misses the reward in 7 sessions (seeds
    // 131, 140, 312, 545, 623, 685, 930), the relaxed E3D in none (0 of
    // 10 000 measured)
    let e3d = sessions(LearnerKind::E3d, true, 0..1000);
    let relaxed = sessions(LearnerKind::E3dRelax, true, 0..1000);
    let locked = |v: &[(f64, f64, bool)]| v.iter().filter(|s| !s.2).count();
    assert!(locked(&e3d) >= 4, "E3D locked {} times", locked(&e3d));
    assert_eq!(locked(&relaxed), 0);
    // and the reward at the paper's strength: 4440 for E3D, 4455 relaxed
    // (means over 10 000 sessions)
    let (a, b) = (mean(&e3d, |s| s.1), mean(&relaxed, |s| s.1));
    assert!(b > 0.98 * a, "relaxed {b} against E3D {a}");
}

#[test]
fn relaxed_e3d_keeps_task_1_entropy() {
    // 0.985 for E3D, 0.978 relaxed, 0.80 uniform (means of 10 000)
    let e3d = mean(&sessions(LearnerKind::E3d, false, 0..200), |s| s.0);
    let relaxed = mean(&sessions(LearnerKind::E3dRelax, false, 0..200), |s| s.0);
    assert!(relaxed > 0.97, "{relaxed}");
    assert!(relaxed > e3d - 0.015, "{relaxed} against {e3d}");
}

#[test]
fn count_bonus_and_smm_explore_better_than_uniform() {
    // 200 sessions of task 1: uniform 0.80, count 0.87, smm 0.89
    let uniform = mean(&sessions(LearnerKind::Uniform, false, 0..200), |s| s.0);
    let count = mean(&sessions(LearnerKind::Count, false, 0..200), |s| s.0);
    let smm = mean(&sessions(LearnerKind::Smm, false, 0..200), |s| s.0);
    assert!((uniform - 0.80).abs() < 0.01, "{uniform}");
    assert!(count > uniform + 0.05, "count {count}");
    assert!(smm > uniform + 0.06, "smm {smm}");
}

fn outcome(effect: usize, reward: f64) -> Outcome {
    Outcome {
        effect,
        reward,
        point: [0.0; 2],
    }
}

#[test]
fn with_rho_zero_the_relaxed_update_is_e3d_s() {
    // the same updates as E3D's (to rounding) when rho = 0, over a session
    let (scene, table) = two_rooms();
    let space = scene.command_space();
    let mut plain = RelaxedE3d::new(&space, 18, &Params::TASK2, &Target::Uniform)
        .unwrap()
        .with_relax(0.0)
        .unwrap();
    let mut e3d = e3d::learner::E3d::new(&space, 18, &Params::TASK2, &Target::Uniform).unwrap();
    let mut c = space.first();
    for i in 0..2000u64 {
        space.write_command_at((i * 7919) % 16384, &mut c);
        let o = *table.lookup(&c).unwrap();
        plain.learn(&c, &o);
        e3d.learn(&c, &o);
    }
    for slot in 0..7 {
        for (a, b) in plain.q(slot).iter().zip(e3d.q(slot)) {
            assert!((a - b).abs() < 1e-9, "slot {slot}: {a} vs {b}");
        }
    }
    assert!(
        RelaxedE3d::new(&space, 18, &Params::TASK2, &Target::Uniform)
            .unwrap()
            .with_relax(-1.0)
            .is_err()
    );
}

#[test]
fn count_bonus_counts_and_smm_keeps_a_bounded_history() {
    let space = e3d::command::CommandSpace::repeat(2, &['a', 'b']).unwrap();
    let mut count = CountBonus::new(&space, 3, &Params::TASK1);
    let mut smm = StateMarginalMatching::new(&space, 3, &Params::TASK1, &Target::Uniform).unwrap();
    let c = Command::new(vec![1, 0]);
    for t in 0..100_000 {
        count.learn(&c, &outcome(t % 3, 0.0));
        smm.learn(&c, &outcome(t % 3, 0.0));
    }
    assert_eq!(
        (count.count(0), count.count(1), count.count(2)),
        (33_334, 33_333, 33_333)
    );
    // 100 000 trials at one copy per 50, halved past 256: between 128 and 256
    let kept = smm.num_snapshots();
    assert!((128..=256).contains(&kept), "{kept}");
    // an even histogram matches the uniform target: smm's drive is about 0
    // while count's bonus is positive
    assert!(smm.q(0)[1].abs() < 1e-3, "{}", smm.q(0)[1]);
    assert!(count.q(0)[1] > 0.0);
    assert_eq!(count.name(), "count");
    assert_eq!(smm.name(), "smm");
}

#[test]
fn every_learner_is_named_on_the_command_line() {
    for kind in LearnerKind::ALL {
        assert_eq!(kind.as_str().parse::<LearnerKind>().unwrap(), kind);
        if kind == LearnerKind::QlearningMoves {
            continue; // a learner of episodes only (tests/library/contexts.rs)
        }
        let (scene, _) = two_rooms();
        let l = LearnerSetup::new(kind)
            .symbols(&scene.command_space(), 18)
            .unwrap();
        assert_eq!(l.name(), kind.as_str());
    }
    let e = "e3d-relax".parse::<LearnerKind>().unwrap_err();
    assert_eq!(
        e.to_string(),
        "unknown learner `e3d-relax`; expected one of: e3d, uniform, egreedy, e3d_relax, count, smm, goal_babbling, archive, archive_reached, map_elites, qlearning_moves"
    );
    assert_eq!(e.input(), "e3d-relax");
}

/// State marginal matching as docs/algorithms.md writes it, line by line:
/// `N(e)`, `t`, `rho(e) = (N(e) + 1) / (t + |E|)`, the update of every
/// chosen symbol with the drive `log p*(e) - log rho(e)`, a copy of `Q`
/// kept every 50 trials (past 256 copies, the later of each pair kept and
/// the interval doubled), and proposals from a copy drawn uniformly among
/// the kept ones and the current `Q`.
struct PlainSmm {
    q: Vec<Vec<f64>>,
    n: Vec<f64>,
    t: f64,
    copies: Vec<Vec<Vec<f64>>>,
    every: u64,
    p: Params,
}

impl PlainSmm {
    fn propose(&self, rng: &mut e3d::SessionRng) -> Vec<u8> {
        use rand::RngExt;
        let k = rng.random_range(0..=self.copies.len());
        let q = self.copies.get(k).unwrap_or(&self.q);
        q.iter()
            .map(|qs| {
                let w: Vec<f64> = qs.iter().map(|v| (self.p.beta * v).exp()).collect();
                let z: f64 = w.iter().sum();
                let u: f64 = rng.random();
                let mut cum = 0.0;
                for (a, wa) in w.iter().enumerate() {
                    cum += wa / z;
                    if u < cum {
                        return a as u8;
                    }
                }
                (qs.len() - 1) as u8
            })
            .collect()
    }

    fn learn(&mut self, c: &[u8], e: usize, r: f64) {
        let Params {
            alpha,
            beta,
            lambda,
            ..
        } = self.p;
        let effects = self.n.len() as f64;
        self.n[e] += 1.0;
        self.t += 1.0;
        let rho = (self.n[e] + 1.0) / (self.t + effects);
        let drive = (1.0 / effects).ln() - rho.ln();
        for (slot, &a) in c.iter().enumerate() {
            let q = &mut self.q[slot][a as usize];
            *q = (1.0 - alpha * lambda) * *q + alpha * lambda * r + alpha / beta * drive;
        }
        if self.t as u64 % self.every == 0 {
            self.copies.push(self.q.clone());
            if self.copies.len() > 256 {
                self.copies = std::mem::take(&mut self.copies)
                    .into_iter()
                    .enumerate()
                    .filter(|(i, _)| i % 2 == 1)
                    .map(|(_, q)| q)
                    .collect();
                self.every *= 2;
            }
        }
    }
}

#[test]
fn smm_follows_its_plain_transcription() {
    use rand::SeedableRng;
    let (scene, table) = two_rooms();
    let space = scene.command_space();
    // small Q values (beta 1) keep the softmax weights unscaled in the plain
    // form; 14000 trials pass the 256 copies, so the thinning runs once
    let p = Params {
        beta: 1.0,
        ..Params::TASK2
    };
    let effects = scene.num_effects();
    let mut fast = StateMarginalMatching::new(&space, effects, &p, &Target::Uniform).unwrap();
    let mut plain = PlainSmm {
        q: vec![vec![0.0; 4]; 7],
        n: vec![0.0; effects],
        t: 0.0,
        copies: Vec::new(),
        every: 50,
        p,
    };
    let (mut ra, mut rb) = (
        e3d::SessionRng::seed_from_u64(11),
        e3d::SessionRng::seed_from_u64(11),
    );
    let mut c = space.first();
    let (trials, mut same, mut rewarded) = (14_000, 0, 0);
    for _ in 0..trials {
        fast.propose(&mut ra, &mut c);
        let cp = Command::new(plain.propose(&mut rb));
        same += usize::from(c == cp);
        // both learn the plain form's command, so that a draw rounded the
        // other way does not part them
        let o = table.lookup(&cp).unwrap();
        rewarded += usize::from(o.reward > 0.0);
        fast.learn(&cp, o);
        plain.learn(&cp.symbols, o.effect, o.reward);
    }
    assert!(same >= trials - 10, "{same} of {trials} commands equal");
    assert!(rewarded > 0, "the reward term was exercised");
    // 257 copies at trial 12850, thinned to 128, then one every 100 trials
    // from 12900 to 14000
    assert_eq!(fast.num_snapshots(), 128 + 12);
    assert_eq!(fast.num_snapshots(), plain.copies.len());
    for (slot, want) in plain.q.iter().enumerate() {
        for (a, b) in fast.q(slot).iter().zip(want) {
            assert!((a - b).abs() < 1e-9, "slot {slot}: {a} vs {b}");
        }
    }
}
