//! Codes of planning requests: a leaf module, so the reports that use them do not
//! depend on each other.

use cellc_lang::Code;
/// The request names something the cell does not have, or a pose matches no state.
pub const LOCATE: Code = Code("R0003");
/// No plan reaches the goal.
pub const UNREACHABLE: Code = Code("R0004");
/// No request to plan: the cell declares none, or none of that name.
pub const NO_REQUEST: Code = Code("R0005");
/// The request's time budget ran out.
pub const TIME_BUDGET: Code = Code("R0006");
/// Executing a plan failed for good: before the object left its start, or too often.
pub const EXECUTION_FAILED: Code = Code("R0007");
/// A world document that cannot be read (not JSON of its shape, or too large).
pub const WORLD_DOCUMENT: Code = Code("R0008");
/// A world that names what the cell lacks, a joint out of limits, or a placement that
/// matches no state.
pub const WORLD: Code = Code("R0009");
/// The goal is where another object of the world stands, or the object is absent.
pub const GOAL_OCCUPIED: Code = Code("R0010");
/// A plan document (`cellc view --plan FILE`) that cannot be read or does not fit the
/// cell.
pub const PLAN_DOCUMENT: Code = Code("R0011");
/// Every code of this phase.
pub const ALL: &[Code] = &[
    LOCATE,
    UNREACHABLE,
    NO_REQUEST,
    TIME_BUDGET,
    EXECUTION_FAILED,
    WORLD_DOCUMENT,
    WORLD,
    GOAL_OCCUPIED,
    PLAN_DOCUMENT,
];
