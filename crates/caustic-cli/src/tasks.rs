//! Array jobs: the task index a scheduler gives each element, the sample range it picks, and
//! `{index}` placeholders in file names.

use anyhow::{Context, bail};
use std::ops::Range;

/// The variables that carry an array element's index, in the order they are read.
pub const INDEX_VARIABLES: [&str; 2] = [
    // Kubernetes Indexed Job (completionMode: Indexed).
    "JOB_COMPLETION_INDEX",
    // Slurm job array (sbatch --array).
    "SLURM_ARRAY_TASK_ID",
];

/// An array element's index and the variable it came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TaskIndex {
    /// The index (0-based for Kubernetes; whatever `--array` lists for Slurm).
    pub index: u32,
    /// The variable it was read from.
    pub variable: &'static str,
}

impl TaskIndex {
    /// Reads the index from the scheduler's variables through `lookup` (the process environment
    /// in the binary). Unset, empty, non-numeric or negative values, two variables that disagree,
    /// and an index at or beyond `tasks` are errors naming the variable.
    pub fn from_env(lookup: impl Fn(&str) -> Option<String>, tasks: Option<u32>) -> anyhow::Result<TaskIndex> {
        let mut found: Option<TaskIndex> = None;
        for variable in INDEX_VARIABLES {
            let Some(text) = lookup(variable) else { continue };
            let index =
                text.trim().parse::<u32>().with_context(|| format!("{variable}='{text}' is not a task index (a whole number from 0 to {})", u32::MAX))?;
            if let Some(first) = &found {
                if first.index != index {
                    bail!("{}={} and {variable}={index} are both set and disagree: which task is this?", first.variable, first.index);
                }
            } else {
                found = Some(TaskIndex { index, variable });
            }
        }
        let Some(task) = found else {
            bail!("no task index: neither JOB_COMPLETION_INDEX (Kubernetes Indexed Job) nor SLURM_ARRAY_TASK_ID (Slurm job array) is set");
        };
        if let Some(tasks) = tasks {
            if task.index >= tasks {
                bail!("{}={} is out of range: --tasks {tasks} allows indices 0..={}", task.variable, task.index, tasks.saturating_sub(1));
            }
        }
        Ok(task)
    }

    /// The sample range of this task when each renders `spp_per_task` samples:
    /// `index * spp_per_task .. (index + 1) * spp_per_task`.
    pub fn sample_range(&self, spp_per_task: u32) -> anyhow::Result<Range<u32>> {
        if spp_per_task == 0 {
            crate::failure::usage!("--spp-per-task 0: each task needs at least one sample per pixel");
        }
        let start = self.index.checked_mul(spp_per_task);
        let end = start.and_then(|s| s.checked_add(spp_per_task));
        match (start, end) {
            (Some(start), Some(end)) => Ok(start..end),
            _ => bail!(
                "{}={} is out of range: with --spp-per-task {spp_per_task} its samples would pass the last sample index {}",
                self.variable,
                self.index,
                u32::MAX
            ),
        }
    }
}

/// Whether `text` holds an `{index}` or `{index:0N}` placeholder.
pub fn has_placeholder(text: &str) -> bool {
    text.contains("{index}") || text.contains("{index:")
}

/// Replaces every `{index}` in `text` by `index`, and every `{index:0N}` by `index` zero-padded
/// to N digits (N from 1 to 9).
pub fn substitute(text: &str, index: u32) -> anyhow::Result<String> {
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find("{index") {
        out.push_str(&rest[..at]);
        let after = &rest[at + "{index".len()..];
        let close = after.find('}').with_context(|| format!("'{text}': unclosed {{index placeholder"))?;
        let spec = &after[..close];
        let formatted = match spec {
            "" => index.to_string(),
            _ => {
                let width = spec
                    .strip_prefix(":0")
                    .and_then(|w| w.parse::<usize>().ok())
                    .filter(|w| (1..=9).contains(w))
                    .with_context(|| format!("'{text}': placeholder {{index{spec}}} is neither {{index}} nor {{index:0N}} with N from 1 to 9"))?;
                format!("{index:0width$}")
            }
        };
        out.push_str(&formatted);
        rest = &after[close + 1..];
    }
    out.push_str(rest);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(pairs: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |name| pairs.iter().find(|(k, _)| *k == name).map(|(_, v)| v.to_string())
    }

    #[test]
    fn reads_either_scheduler() {
        let k8s = TaskIndex::from_env(env(&[("JOB_COMPLETION_INDEX", "3")]), Some(4)).unwrap();
        assert_eq!(k8s, TaskIndex { index: 3, variable: "JOB_COMPLETION_INDEX" });
        let slurm = TaskIndex::from_env(env(&[("SLURM_ARRAY_TASK_ID", "7")]), None).unwrap();
        assert_eq!(slurm.index, 7);
        assert_eq!(slurm.sample_range(64).unwrap(), 448..512);
        let both = TaskIndex::from_env(env(&[("JOB_COMPLETION_INDEX", "2"), ("SLURM_ARRAY_TASK_ID", "2")]), None).unwrap();
        assert_eq!(both.index, 2);
    }

    #[test]
    fn bad_values_are_clear_errors() {
        let error = |pairs: &[(&str, &str)], tasks| TaskIndex::from_env(env(pairs), tasks).unwrap_err().to_string();
        assert!(error(&[], None).contains("JOB_COMPLETION_INDEX"));
        assert!(error(&[("SLURM_ARRAY_TASK_ID", "x1")], None).contains("SLURM_ARRAY_TASK_ID='x1'"));
        assert!(error(&[("JOB_COMPLETION_INDEX", "-1")], None).contains("JOB_COMPLETION_INDEX='-1'"));
        assert!(error(&[("JOB_COMPLETION_INDEX", "")], None).contains("not a task index"));
        assert!(error(&[("JOB_COMPLETION_INDEX", "4")], Some(4)).contains("out of range"));
        assert!(error(&[("JOB_COMPLETION_INDEX", "1"), ("SLURM_ARRAY_TASK_ID", "2")], None).contains("disagree"));
        let huge = TaskIndex { index: u32::MAX / 2, variable: "SLURM_ARRAY_TASK_ID" };
        assert!(huge.sample_range(4).unwrap_err().to_string().contains("out of range"));
    }

    #[test]
    fn placeholders() {
        assert_eq!(substitute("part-{index}.exr", 12).unwrap(), "part-12.exr");
        assert_eq!(substitute("f{index:04}/{index}.glb", 7).unwrap(), "f0007/7.glb");
        assert_eq!(substitute("plain.exr", 7).unwrap(), "plain.exr");
        assert!(substitute("a{index:4}.exr", 1).is_err());
        assert!(substitute("a{index.exr", 1).is_err());
        assert!(has_placeholder("x{index:03}") && !has_placeholder("x.exr"));
    }
}
