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
}

impl FrontEnd {
    /// How this front end's caller writes `option` (in backticks, as advice quotes it).
    pub fn option(self, option: PlanOption) -> &'static str {
        match (self, option) {
            (FrontEnd::CommandLine, PlanOption::TimeBudget) => "`--time-budget`",
            (FrontEnd::CommandLine, PlanOption::Clear) => "`--clear`",
            (FrontEnd::CommandLine, PlanOption::Seed) => "`--seed`",
            (FrontEnd::Service, PlanOption::TimeBudget) => "`time_budget_ms`",
            (FrontEnd::Service, PlanOption::Clear) => "`\"clear\": true`",
            (FrontEnd::Service, PlanOption::Seed) => "`seed`",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_front_end_names_its_own_options() {
        for option in [PlanOption::TimeBudget, PlanOption::Clear, PlanOption::Seed] {
            assert!(FrontEnd::CommandLine.option(option).starts_with("`--"));
            assert!(!FrontEnd::Service.option(option).contains("--"));
        }
    }
}
