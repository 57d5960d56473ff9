//! Which front end asked, so advice names the caller's own option: a flag on the command
//! line (`--time-budget`), a field of the request's JSON in the service
//! (`time_budget_ms`). The words are chosen when the advice is written, never patched.

/// The front end a diagnostic is written for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FrontEnd {
    /// `cellc plan`, `cellc run` and the other commands: options are flags.
    #[default]
    CommandLine,
    /// `cellc serve`: options are fields of the request's `options`.
    Service,
}

/// A planning option that advice may name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlanOption {
    /// The planning time budget.
    TimeBudget,
    /// Moving objects in the way out of it first.
    Clear,
    /// The seed of sampling.
    Seed,
    /// The share of every joint's velocity limit the motions use.
    VelocityScaling,
    /// The share of every joint's acceleration (and jerk) limit the motions use.
    AccelerationScaling,
    /// The control rate trajectories are resampled at.
    Rate,
}

impl PlanOption {
    /// The option of a field of the runtime's `TimingOptions` (the name its
    /// `InvalidOption` errors carry), if it is one a caller sets.
    pub fn of_timing_field(name: &str) -> Option<PlanOption> {
        match name {
            "velocity_scaling" => Some(PlanOption::VelocityScaling),
            "acceleration_scaling" => Some(PlanOption::AccelerationScaling),
            "rate" => Some(PlanOption::Rate),
            _ => None,
        }
    }
}

impl FrontEnd {
    /// How this front end's caller writes `option` (in backticks, as advice quotes it).
    pub fn option(self, option: PlanOption) -> &'static str {
        match (self, option) {
            (FrontEnd::CommandLine, PlanOption::TimeBudget) => "`--time-budget`",
            (FrontEnd::CommandLine, PlanOption::Clear) => "`--clear`",
            (FrontEnd::CommandLine, PlanOption::Seed) => "`--seed`",
            (FrontEnd::CommandLine, PlanOption::VelocityScaling) => "`--velocity-scaling`",
            (FrontEnd::CommandLine, PlanOption::AccelerationScaling) => "`--acceleration-scaling`",
            (FrontEnd::CommandLine, PlanOption::Rate) => "`--rate`",
            (FrontEnd::Service, PlanOption::TimeBudget) => "`time_budget_ms`",
            (FrontEnd::Service, PlanOption::Clear) => "`\"clear\": true`",
            (FrontEnd::Service, PlanOption::Seed) => "`seed`",
            (FrontEnd::Service, PlanOption::VelocityScaling) => "`velocity_scaling`",
            (FrontEnd::Service, PlanOption::AccelerationScaling) => "`acceleration_scaling`",
            (FrontEnd::Service, PlanOption::Rate) => "`rate`",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_front_end_names_its_own_options() {
        for option in [
            PlanOption::TimeBudget,
            PlanOption::Clear,
            PlanOption::Seed,
            PlanOption::VelocityScaling,
            PlanOption::AccelerationScaling,
            PlanOption::Rate,
        ] {
            assert!(FrontEnd::CommandLine.option(option).starts_with("`--"));
            assert!(!FrontEnd::Service.option(option).contains("--"));
        }
        // The service's words are the runtime's field names, which its errors carry.
        for name in ["velocity_scaling", "acceleration_scaling", "rate"] {
            let option = PlanOption::of_timing_field(name).unwrap();
            assert_eq!(FrontEnd::Service.option(option), format!("`{name}`"));
        }
    }
}
