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
//!
//! A cycle may mix joints and bodies (a slider's car pushed by a `Force`,
//! the arm it carries turned by `Torque`s): then each symbol that names
//! `"*"` is written twice, once with a joint's action (`Torque`,
//! `Target`) and once with a body's (`Force`, `Impulse`), and a slot
//! keeps the one of its entry's kind.
//!
//! ```ron
//! alphabet: [
//!     (symbol: '-', action: Force(body: "*", force: (-4.0, 0.0))),
//!     (symbol: '-', action: Torque(joint: "*", torque: -0.5)),
//!     (symbol: '0', action: Idle),
//!     (symbol: '+', action: Force(body: "*", force: (4.0, 0.0))),
//!     (symbol: '+', action: Torque(joint: "*", torque: 0.5)),
//! ],
//! cycle: ["cart", "j1", "j2"],   // slot 0 pushes the cart, slots 1, 2 turn j1, j2
//! ```

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

/// What `"*"` stands for in `a`: a joint (`Some(true)`, in `Torque`,
/// `Target`), a body (`Some(false)`, in `Impulse`, `Force`), or nothing.
fn star(a: &Action) -> Option<bool> {
    (name_of(a) == Some(PLACEHOLDER))
        .then_some(matches!(a, Action::Torque { .. } | Action::Target { .. }))
}

/// Whether an alphabet's `"*"` names joints in some actions and bodies in
/// others: its cycle mixes joints and bodies.
fn mixes(alphabet: &[SymbolSpec]) -> bool {
    let kinds = |joint| alphabet.iter().any(|s| star(&s.action) == Some(joint));
    kinds(true) && kinds(false)
}

/// Whether the template `command` mixes joints and bodies in its cycle
/// (its expansion needs to know which names are joints).
pub(crate) fn needs_joints(command: &CommandSpec) -> bool {
    matches!(command, CommandSpec::Template { alphabet, .. } if mixes(alphabet))
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
/// `joints`, a body (in `Impulse`, `Force`) among `bodies`, either when
/// the alphabet mixes both (then every symbol naming `"*"` has an action
/// of the entry's kind); `Err` is placed at the entry.
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
    if mixes(alphabet) {
        return check_mixed(alphabet, cycle, joints, bodies);
    }
    let uses = |joint: bool| alphabet.iter().any(|s| star(&s.action) == Some(joint));
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

/// [`check_names`] for an alphabet that mixes joints and bodies: each
/// entry a joint (first) or a body, and every symbol naming `"*"` with
/// an action of that kind.
fn check_mixed(
    alphabet: &[SymbolSpec],
    cycle: &[String],
    joints: &[&str],
    bodies: &[&str],
) -> Result<(), Invalid> {
    for (i, c) in cycle.iter().enumerate() {
        let joint = joints.contains(&c.as_str());
        if !joint && !bodies.contains(&c.as_str()) {
            let known: Vec<&str> = joints.iter().chain(bodies).copied().collect();
            return Err(Invalid::new(
                "cycle",
                format!(
                    "cycle[{i}]: a joint or a body (the alphabet's `*` names joints in some actions, bodies in others), but there is neither `{c}`{}; joints: {}; bodies: {}",
                    super::did_you_mean(c, &known),
                    joints.join(", "),
                    bodies.join(", ")
                ),
            ));
        }
        let (what, actions) = if joint {
            ("joint", "Torque or Target")
        } else {
            ("body", "Force or Impulse")
        };
        let missing = alphabet.iter().find(|s| {
            star(&s.action).is_some()
                && !alphabet
                    .iter()
                    .any(|t| t.symbol == s.symbol && star(&t.action) == Some(joint))
        });
        if let Some(s) = missing {
            return Err(Invalid::new(
                "cycle",
                format!(
                    "cycle[{i}]: `{c}` is a {what}, so every symbol naming `*` needs an action on a {what} ({actions} on \"*\"), but symbol '{}' has none: in a cycle of joints and bodies, write each such symbol twice, once for each",
                    s.symbol
                ),
            ));
        }
    }
    Ok(())
}

/// The `Slots` a `Template` stands for (`None` for any other schema);
/// `Err` names the template's field at fault. `is_joint(name)` says
/// whether a cycle entry is a joint, for an alphabet that mixes joints
/// and bodies ([`needs_joints`]): a slot keeps, of each symbol, the
/// action of its entry's kind.
pub(crate) fn expand(
    command: &CommandSpec,
    is_joint: &dyn Fn(&str) -> bool,
) -> Result<Option<CommandSpec>, Invalid> {
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
    let uses = alphabet.iter().any(|s| star(&s.action).is_some());
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
    let mixed = mixes(alphabet);
    let slots = (0..n)
        .map(|k| {
            let name = (!cycle.is_empty()).then(|| cycle[k % cycle.len()].clone());
            // of a mixed alphabet, the actions of the entry's kind
            let kind = name.as_deref().filter(|_| mixed).map(is_joint);
            SlotSpec {
                alphabet: alphabet
                    .iter()
                    .filter(|s| kind.is_none() || star(&s.action).is_none_or(|j| Some(j) == kind))
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
        let Some(CommandSpec::Slots(s)) = expand(&t, &|_| true).unwrap() else {
            panic!("a template expands to slots")
        };
        let names: Vec<_> = s.iter().map(|s| s.name.clone().unwrap()).collect();
        assert_eq!(names, ["a", "b", "a", "b", "a"]);
        assert_eq!(s[3].alphabet[0].action, torque("b", -1.0));
        assert_eq!(s[3].alphabet[1].action, Action::Idle);
    }

    #[test]
    fn a_mixed_cycle_keeps_the_action_of_each_entrys_kind() {
        let force = |f: f64| Action::Force {
            body: "*".into(),
            force: (f, 0.0),
        };
        let sym = |symbol, action| SymbolSpec { symbol, action };
        let t = CommandSpec::Template {
            slots: 3,
            alphabet: vec![
                sym('-', force(-4.0)),
                sym('-', torque("*", -1.0)),
                sym('0', Action::Idle),
                sym('+', torque("*", 1.0)),
                sym('+', force(4.0)),
            ],
            cycle: vec!["cart".into(), "j1".into()],
        };
        let Some(CommandSpec::Slots(s)) = expand(&t, &|n| n == "j1").unwrap() else {
            panic!("a template expands to slots")
        };
        let actions =
            |k: usize| -> Vec<Action> { s[k].alphabet.iter().map(|s| s.action.clone()).collect() };
        let pushed = |f: f64| Action::Force {
            body: "cart".into(),
            force: (f, 0.0),
        };
        assert_eq!(actions(0), [pushed(-4.0), Action::Idle, pushed(4.0)]);
        assert_eq!(
            actions(1),
            [torque("j1", -1.0), Action::Idle, torque("j1", 1.0)]
        );
        assert_eq!(actions(2), actions(0));
        assert!(check_names(&t, &["j1"], &["cart", "pole"]).is_ok());
        // `pole` is a body: its slot needs a body's action of every symbol
        let mut no_push = t.clone();
        if let CommandSpec::Template { alphabet, .. } = &mut no_push {
            alphabet.remove(4);
        }
        let e = check_names(&no_push, &["j1"], &["cart"]).unwrap_err();
        assert!(format!("{e:?}").contains("symbol '+' has none"), "{e:?}");
        let e = check_names(&t, &["j1"], &["car"]).unwrap_err();
        assert!(
            format!("{e:?}").contains("there is neither `cart`"),
            "{e:?}"
        );
    }
}
