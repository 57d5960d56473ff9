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
/// Every code of this phase.
pub const ALL: &[Code] = &[LOCATE, UNREACHABLE, NO_REQUEST, TIME_BUDGET, EXECUTION_FAILED];
