//! The checks of a scene spec: everything parsing alone cannot check,
//! before the failure is placed in a file ([`SceneSpec::validate`],
//! [`Scene::parse`](super::Scene::parse)).

use super::physics::PhysicsSpec;
use super::{
    printable_symbol, shorthand, template, CommandSpec, Invalid, SceneSpec, WorldSpec, MAX_REWARD,
};
use crate::command::{MAX_ALPHABET, MAX_SLOTS};

impl SceneSpec {
    /// Checks everything that parsing alone cannot (the checks of
    /// [`validate`](SceneSpec::validate), before they are placed in a file).
    pub(super) fn check(&self) -> Result<(), Invalid> {
        if self.name.trim().is_empty() {
            return Err(Invalid::new("name", "a non-empty name"));
        }
        crate::text::check_name(&self.name).map_err(|e| Invalid::new("name", e))?;
        let n = self.slots().count();
        self.check_slot_count(n)?;
        self.check_slot_names()?;
        if matches!(self.command, CommandSpec::Template { .. }) {
            let world = || -> Result<Option<PhysicsSpec>, Invalid> {
                let WorldSpec::Physics(p) = &self.world else {
                    return Ok(None);
                };
                let mut e = p.clone();
                shorthand::expand(&mut e)?;
                Ok(Some(e))
            };
            // a template mixing joints and bodies expands by the joints' names
            let mixed = template::needs_joints(&self.command);
            let mut e = if mixed { world()? } else { None };
            let early: Vec<&str> = e
                .iter()
                .flat_map(|e| &e.joints)
                .map(|j| j.name.as_str())
                .collect();
            let slots = template::expand(&self.command, &|c| early.contains(&c))?
                .expect("a template expands");
            if !mixed {
                e = world()?;
            }
            if let Some(e) = &e {
                let joints: Vec<&str> = e.joints.iter().map(|j| j.name.as_str()).collect();
                let bodies: Vec<&str> = e.bodies.iter().map(|b| b.name.as_str()).collect();
                template::check_names(&self.command, &joints, &bodies)?;
            }
            // every check on the slots the template stands for
            return SceneSpec {
                command: slots,
                slots: None,
                ..self.clone()
            }
            .check();
        }
        if n > MAX_SLOTS {
            return Err(Invalid::new(
                "slots",
                format!("at most {MAX_SLOTS} slots, found {n}"),
            ));
        }
        self.check_ranges()?;
        self.check_alphabets()?;
        self.check_world()?;
        self.check_reward()
    }

    /// The names a `Slots` or `Continuous` schema gives its slots pass the
    /// one name check ([`check_name`](crate::text::check_name)): they are
    /// printed and drawn.
    fn check_slot_names(&self) -> Result<(), Invalid> {
        let names: Vec<&str> = match &self.command {
            CommandSpec::Slots(s) => s.iter().filter_map(|s| s.name.as_deref()).collect(),
            CommandSpec::Continuous(s) => s.iter().filter_map(|s| s.name.as_deref()).collect(),
            _ => Vec::new(),
        };
        for n in names {
            let at = format!("\"{n}\"");
            crate::text::check_name(n)
                .map_err(|e| Invalid::at("name", Some(&at), &format!("slot name: {e}")))?;
        }
        Ok(())
    }

    /// The `n` slots the command lists: as many as the scene's `slots`
    /// declares, if it does, and at least one.
    fn check_slot_count(&self, n: usize) -> Result<(), Invalid> {
        if let Some(declared) = self.slots.filter(|&d| d != n) {
            let (variant, how) = match &self.command {
                CommandSpec::Repeat { .. } => ("Repeat", format!("has `slots: {n}`")),
                CommandSpec::Template { .. } => ("Template", format!("has `slots: {n}`")),
                CommandSpec::Slots(_) => ("Slots", format!("lists {n}")),
                CommandSpec::Continuous(_) => ("Continuous", format!("lists {n}")),
            };
            return Err(Invalid::new(
                variant,
                format!(
                    "{declared} slot(s), as the scene's `slots: {declared}` declares, found {n}: `{variant}` {how}"
                ),
            ));
        }
        if n == 0 {
            return Err(Invalid::new("command", "at least one slot"));
        }
        Ok(())
    }

    /// Continuous slots: in a physics world, each range finite and
    /// increasing.
    fn check_ranges(&self) -> Result<(), Invalid> {
        let CommandSpec::Continuous(slots) = &self.command else {
            return Ok(());
        };
        match &self.world {
            WorldSpec::Grid(_) => return Err(Invalid::new(
                "Continuous",
                "symbols in a Grid world (one-cell moves); continuous slots need a Physics world",
            )),
            // a session of values starts every trial from the scene's
            // start: the contexts would be ignored without a word
            WorldSpec::Physics(p) if !p.contexts.is_empty() => {
                return Err(Invalid::new(
                    "contexts",
                    format!(
                        "no start contexts in a scene whose slots take values (`Continuous`): its sessions start every trial from the scene's start, found {} context(s) (`{}`...); remove `contexts`, or write the slots as symbols",
                        p.contexts.len(),
                        crate::text::echo(&p.contexts[0].name)
                    ),
                ));
            }
            WorldSpec::Physics(_) => {}
        }
        for (i, slot) in slots.iter().enumerate() {
            let (lo, hi) = slot.range;
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(Invalid::new(
                    "range",
                    format!(
                        "slot {i}: a range (min, max) of finite numbers with min < max, found ({lo}, {hi})"
                    ),
                )
                .nth(i));
            }
        }
        Ok(())
    }

    /// The slots' alphabets (a `Repeat` schema's once; none for
    /// continuous slots): 1 to [`MAX_ALPHABET`] distinct printable
    /// symbols each.
    fn check_alphabets(&self) -> Result<(), Invalid> {
        // how often each symbol was written in the alphabets before this
        // slot's (a Repeat schema writes its alphabet once)
        let mut written: std::collections::HashMap<char, usize> = Default::default();
        let slots = match self.command {
            CommandSpec::Continuous(_) => 0,
            CommandSpec::Repeat { .. } => 1,
            _ => usize::MAX,
        };
        let mut written_symbols = 0;
        for (i, alphabet) in self.slots().enumerate().take(slots) {
            let mut here: std::collections::HashSet<char> = Default::default();
            let what = match alphabet.len() {
                0 => "at least one symbol in the alphabet, found none".to_string(),
                n if n > MAX_ALPHABET => format!("at most {MAX_ALPHABET} symbols, found {n}"),
                _ => String::new(),
            };
            if !what.is_empty() {
                return Err(Invalid::new("alphabet", format!("slot {i}: {what}")));
            }
            for s in alphabet {
                if !here.insert(s.symbol) {
                    let before = written.get(&s.symbol).copied().unwrap_or(0);
                    return Err(Invalid::at(
                        "symbol",
                        Some(&format!("'{}'", s.symbol)),
                        &format!(
                            "slot {i}: distinct symbols, but '{}' appears twice",
                            s.symbol
                        ),
                    )
                    .nth(before + 1));
                }
                if !printable_symbol(s.symbol) {
                    return Err(Invalid::new(
                        "symbol",
                        format!(
                            "a printable symbol other than ',' and '\"' (commands are written as strings and CSV fields): not whitespace, a control, format (zero-width) or combining character, found U+{:04X}",
                            u32::from(s.symbol)
                        ),
                    )
                    .nth(written_symbols));
                }
                written_symbols += 1;
            }
            for c in here {
                *written.entry(c).or_insert(0) += 1;
            }
        }
        Ok(())
    }

    /// The world's checks (a physics world's on its expanded shorthands,
    /// an error placed at the shorthand that generated the item).
    fn check_world(&self) -> Result<(), Invalid> {
        match &self.world {
            WorldSpec::Grid(g) => g.validate(self),
            WorldSpec::Physics(p) if p.has_shorthands() => {
                // every check on the generated items, an error on one of
                // them placed at the shorthand that generated it
                let mut e = p.clone();
                let origins = shorthand::expand(&mut e)?;
                e.validate(self).map_err(|v| v.attributed(&origins))
            }
            WorldSpec::Physics(p) => p.validate(self),
        }
    }

    /// The reward: a finite value, cells and regions inside the effect
    /// grid (after [`check_world`](Self::check_world)).
    fn check_reward(&self) -> Result<(), Invalid> {
        // the world's checks above refuse an effect that does not validate
        let Some(grid) = self.effect_grid() else {
            return Err(Invalid::new(
                "effect",
                "an effect that bins terminal states",
            ));
        };
        if !(self.reward.value.is_finite() && self.reward.value.abs() <= MAX_REWARD) {
            return Err(Invalid::new(
                "value",
                format!(
                    "a finite reward value of at most {MAX_REWARD:e} in magnitude (a cumulative reward over 10^8 trials stays finite), found {}",
                    self.reward.value
                ),
            ));
        }
        for &(r, c) in &self.reward.cells {
            if r >= grid.rows || c >= grid.cols {
                return Err(Invalid::new(
                    "cells",
                    format!(
                        "reward cells inside the {} x {} effect grid, found ({r}, {c})",
                        grid.rows, grid.cols
                    ),
                ));
            }
        }
        for region in &self.reward.regions {
            region.validate(&grid)?;
        }
        Ok(())
    }
}
