//! Hashing and seed derivation: the 64-bit FNV-1a hash that keys outcome
//! tables, checksums journals and identifies sweeps, and the SplitMix64
//! rule that turns a base seed and a session's identity into the session's
//! seed. Both are documented, portable rules: the same bytes give the same
//! numbers on every machine and in every version.

/// 64-bit FNV-1a of `bytes` (offset basis `0xcbf29ce484222325`, prime
/// `0x100000001b3`).
///
/// ```
/// assert_eq!(e3d::hash::fnv1a64(b""), 0xcbf29ce484222325);
/// assert_eq!(e3d::hash::fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
/// ```
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The SplitMix64 finaliser of `x + 0x9e3779b97f4a7c15` (Steele, Lea and
/// Flood 2014): one step of the SplitMix64 generator seeded with `x`.
///
/// ```
/// assert_eq!(e3d::hash::splitmix64(0), 0xe220a8397b1dcdaf);
/// ```
pub fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The seed of a session: `splitmix64(splitmix64(base) ^ fnv1a64(identity))`,
/// where `identity` is the session's canonical text (see
/// [`sweep`](crate::sweep), "Seeds").
pub fn session_seed(base: u64, identity: &str) -> u64 {
    splitmix64(splitmix64(base) ^ fnv1a64(identity.as_bytes()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeds_are_fixed_by_identity() {
        // a documented, portable rule: these numbers must never change
        assert_eq!(splitmix64(1), 0x910a2dec89025cc1);
        let id = "scene=two_rooms;learner=e3d;use_reward=true;alpha=0.3;beta=100;lambda=0.03;eta=0.01;epsilon=-;session=0";
        assert_eq!(session_seed(0, id), session_seed(0, id));
        assert_ne!(session_seed(0, id), session_seed(1, id));
    }
}
