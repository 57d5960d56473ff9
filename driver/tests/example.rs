//! Runs the front-door example, so `cargo test` proves it works and not only compiles.

#[path = "../examples/plan_vito.rs"]
#[allow(dead_code)]
mod plan_vito;

#[test]
fn the_vito_example_plans_and_executes() {
    // The request by name: the test harness's own arguments are not the example's.
    plan_vito::run("handoff_cylinder").expect("the example runs");
}
