//! What a sweep of episodes asks of its scenes: their start contexts, and
//! the checks of the sweep's episode fields and per-context metrics
//! against them (read while the sweep is planned, before
//! [`episodes`](super::episodes) runs it).

use super::spec::{MetricSpec, SweepSpec};
use super::{SweepError, SweepScene};
use crate::learner::LearnerKind;
use std::sync::Arc;

/// The start contexts of each scene: those of a world of its scene file,
/// 1 for a scene made by code.
pub(super) fn start_contexts(scenes: &[Arc<SweepScene>]) -> Vec<usize> {
    scenes
        .iter()
        .map(|s| s.scene().map_or(1, |scene| scene.build().num_contexts()))
        .collect()
}

/// Checks what a sweep of episodes needs, and adds the per-context
/// entropies, cumulative rewards and first rewarded episodes to the
/// default metrics when a scene has several start contexts.
pub(super) fn check(
    spec: &SweepSpec,
    contexts: &[usize],
    metrics: &mut Vec<MetricSpec>,
    bad: &dyn Fn(&str, Option<&str>, &str) -> SweepError,
) -> Result<(), SweepError> {
    let most = contexts.iter().copied().max().unwrap_or(1);
    let episodes = spec.runs_episodes() || most > 1;
    if !episodes {
        if let Some((name, _)) = metrics.iter().find_map(MetricSpec::per_context) {
            let expected = format!("{name}(I) only in a sweep of episodes (a scene with start contexts, or commands, observe or closed_loop set)");
            return Err(bad("metrics", Some(name), &expected));
        }
        return Ok(());
    }
    for name in &spec.learners {
        if name.parse::<LearnerKind>().is_err() {
            let expected = format!("built-in learners in a sweep of episodes (a scene with start contexts, or commands, observe or closed_loop set), found `{name}`");
            return Err(bad("learners", None, &expected));
        }
    }
    if spec.metrics.is_none() && most > 1 {
        metrics.extend((0..most).map(MetricSpec::NormalizedEntropyContext));
        metrics.extend((0..most).map(MetricSpec::CumulativeRewardContext));
        metrics.extend((0..most).map(MetricSpec::FirstRewardTrialContext));
    }
    for m in metrics.iter() {
        if let Some((name, i)) = m.per_context().filter(|&(_, i)| i >= most) {
            let expected = format!("{name}(I) with I below {most} (the most start contexts of the sweep's scenes), found {i}");
            return Err(bad("metrics", Some(name), &expected));
        }
    }
    Ok(())
}
