//! Slot templates: one alphabet for many slots, slot `k` acting on the
//! joint or body `cycle[k mod m]`.
//!
//! ```ron
//! command: Template(
//!     slots: 6,
//!     alphabet: [
//!         (symbol: '-', action: Torque(joint: "*", torque: -0.5)),
//!         (symbol: '0', action: Idle),
//!         (symbol: '+', action: Torque(joint: "*", torque: 0.5)),
//!     ],
//!     cycle: ["j1", "j2"],   // slot k: `*` stands for cycle[k mod 2]
//! ),
//! ```
//!
//! A template is expanded at load, like the shorthands of a physics world:
//! a loaded scene holds the equivalent [`CommandSpec::Slots`], slot `k`
//! named `cycle[k mod m]` (unnamed without a cycle), every `"*"` of its
//! alphabet replaced by that name. Everything that reads a scene reads
//! its slots as if they were written one by one.

use super::{Action, CommandSpec, Invalid, SlotSpec, SymbolSpec};
use crate::command::MAX_SLOTS;

/// The name that stands for `cycle[k mod m]` in a template's actions.
pub const PLACEHOLDER: &str = "*";

/// The joint or body name of an action (`None` for `Idle`, `Move`).
fn name_of(a: &Action) -> Option<&str> {
    match a {
        Action::Torque { joint, .. } | Action::Target { joint, .. } => Some(joint),
        Action::Impulse { body, .. } | Action::Force { body, .. } => Some(body),
        Action::Idle | Action::Move { .. } => None,
    }
}

/// `a` with its joint or body name `*` replaced by `name`.
fn filled(a: &Action, name: &str) -> Action {
    let mut a = a.clone();
    match &mut a {
        Action::Torque { joint, .. } | Action::Target { joint, .. } if joint == PLACEHOLDER => {
            *joint = name.to_string()
        }
        Action::Impulse { body, .. } | Action::Force { body, .. } if body == PLACEHOLDER => {
            *body = name.to_string()
        }
        _ => {}
    }
    a
}

/// Checks that every entry of a template's `cycle` names what the
/// alphabet's `"*"` stands for: a joint (in `Torque`, `Target`) among
/// `joints`, a body (in `Impulse`, `Force`) among `bodies`; `Err` is
/// placed at the entry.
pub(crate) fn check_names(
    command: &CommandSpec,
    joints: &[&str],
    bodies: &[&str],
) -> Result<(), Invalid> {
    let CommandSpec::Template {
        alphabet, cycle, ..
    } = command
    else {
        return Ok(());
    };
    let uses = |joint: bool| {
        alphabet.iter().any(|s| {
            name_of(&s.action) == Some(PLACEHOLDER)
                && matches!(s.action, Action::Torque { .. } | Action::Target { .. }) == joint
        })
    };
    for (i, c) in cycle.iter().enumerate() {
        for (joint, known, what) in [(true, joints, "joint"), (false, bodies, "body")] {
            if uses(joint) && !known.contains(&c.as_str()) {
                return Err(Invalid::at(
                    "cycle",
                    Some(&format!("\"{c}\"")),
                    &format!(
                        "cycle[{i}]: a {what} (the alphabet's `*` names a {what}), but there is no {what} `{c}`{}; {what}s: {}",
                        super::did_you_mean(c, known),
                        known.join(", ")
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The `Slots` a `Template` stands for (`None` for any other schema);
/// `Err` names the template's field at fault.
pub(crate) fn expand(command: &CommandSpec) -> Result<Option<CommandSpec>, Invalid> {
    let CommandSpec::Template {
        slots,
        alphabet,
        cycle,
    } = command
    else {
        return Ok(None);
    };
    let n = *slots;
    if n == 0 || n > MAX_SLOTS {
        return Err(Invalid::new(
            "slots",
            format!("between 1 and {MAX_SLOTS} slots, found {n}"),
        ));
    }
    if let Some(bad) = cycle
        .iter()
        .position(|c| c.trim().is_empty() || c == PLACEHOLDER)
    {
        return Err(Invalid::new(
            "cycle",
            format!(
                "joint or body names in the cycle (not empty, not `*`), found `{}` at position {bad}",
                cycle[bad]
            ),
        ));
    }
    let uses = alphabet
        .iter()
        .any(|s| name_of(&s.action) == Some(PLACEHOLDER));
    if uses && cycle.is_empty() {
        return Err(Invalid::at(
            "cycle",
            Some(PLACEHOLDER),
            "a `cycle: [\"name\", ...]` of the joints or bodies that `*` stands for (slot k takes cycle[k mod m]), found none",
        ));
    }
    if !uses && !cycle.is_empty() {
        return Err(Invalid::new(
            "cycle",
            "an action naming `*` (the cycle's joint or body) in the alphabet, found none: without `*` the cycle does nothing (write `Repeat` for one alphabet on every slot)",
        ));
    }
    let slots = (0..n)
        .map(|k| {
            let name = (!cycle.is_empty()).then(|| cycle[k % cycle.len()].clone());
            SlotSpec {
                alphabet: alphabet
                    .iter()
                    .map(|s| SymbolSpec {
                        symbol: s.symbol,
                        action: name
                            .as_ref()
                            .map_or(s.action.clone(), |c| filled(&s.action, c)),
                    })
                    .collect(),
                name,
            }
        })
        .collect();
    Ok(Some(CommandSpec::Slots(slots)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn torque(joint: &str, t: f64) -> Action {
        Action::Torque {
            joint: joint.into(),
            torque: t,
        }
    }

    #[test]
    fn slot_k_takes_cycle_k_mod_m() {
        let t = CommandSpec::Template {
            slots: 5,
            alphabet: vec![
                SymbolSpec {
                    symbol: '-',
                    action: torque("*", -1.0),
                },
                SymbolSpec {
                    symbol: '0',
                    action: Action::Idle,
                },
            ],
            cycle: vec!["a".into(), "b".into()],
        };
        let Some(CommandSpec::Slots(s)) = expand(&t).unwrap() else {
            panic!("a template expands to slots")
        };
        let names: Vec<_> = s.iter().map(|s| s.name.clone().unwrap()).collect();
        assert_eq!(names, ["a", "b", "a", "b", "a"]);
        assert_eq!(s[3].alphabet[0].action, torque("b", -1.0));
        assert_eq!(s[3].alphabet[1].action, Action::Idle);
    }
}
