//! Randomness: the generator every session draws from, and how it is
//! seeded.
//!
//! A session's draws come from one [`SessionRng`] seeded with the
//! session's seed, so the same seed gives the same trials on every
//! machine, whatever the number of threads. Learners receive it in
//! [`Learner::propose`](crate::Learner::propose) and draw with the traits
//! of [`rand`] (re-exported as `e3d::rand`, so a learner needs no rand of
//! its own).
//!
//! ```
//! use e3d::rand::{RngExt, SeedableRng};
//! use e3d::rng::SessionRng;
//! let mut a = SessionRng::seed_from_u64(7);
//! let mut b = SessionRng::seed_from_u64(7);
//! let x: f64 = a.random();
//! assert_eq!(x, b.random::<f64>());
//! assert!(a.random_range(0..4) < 4);
//! ```

/// The random generator of a session: PCG 64-bit MCG (`rand_pcg::Pcg64Mcg`),
/// portable and fixed by its seed. A session seeded with `s` uses
/// `SessionRng::seed_from_u64(s)`.
pub type SessionRng = rand_pcg::Pcg64Mcg;
