//! `POST /v1/plan/follow_joint_trajectory`: a move planned as `POST /v1/plan` plans it,
//! answered as the plans' motions in the shape of `control_msgs/action/FollowJointTrajectory`
//! goals (`cellc_driver::document::controller`, what `cellc plan --emit
//! follow-joint-trajectory` writes), for a bridge that sends each to its arm's controller.
//! A move with no plan is answered with its diagnostics report alone: no goal of a plan
//! that does not reach its goal is ever given.

use axum::body::Body;
use axum::extract::State;
use axum::response::{IntoResponse, Response};
use axum::Json;
use cellc_driver::document::controller::ControllerGoals;

use super::errors::{ApiError, Failure};
use super::routes::{blocking, plan_body, plan_documents, task_failure, MoveBody, Shared};
use super::{read_json, MAX_BODY};

/// `POST /v1/plan/follow_joint_trajectory`: plans against a copy of the world, as
/// `POST /v1/plan` does; the world is not changed.
pub async fn follow_joint_trajectory(State(service): Shared, body: Body) -> Response {
    let body: MoveBody = match read_json(body, MAX_BODY).await {
        Ok(b) => b,
        Err(e) => return e.into_response(),
    };
    blocking(service, move |service, cancel| {
        let planned = match plan_body(service, &body, cancel) {
            Ok(p) => p,
            Err(e) => return e.into_response(),
        };
        let sources = service.loaded.sources();
        if let Some(failure) = &planned.failure {
            let d = task_failure(service, &failure.error);
            return ApiError::from_diagnostic(Failure::of_task(&failure.error), &d, sources)
                .into_response();
        }
        match ControllerGoals::of(&plan_documents(service, &planned)) {
            Ok(goals) => Json(goals).into_response(),
            // The service's own plans: a motion the runtime would not write is its fault.
            Err(e) => ApiError::from_diagnostic(
                Failure::Internal,
                &crate::plan_report::goals_refused(&e),
                sources,
            )
            .into_response(),
        }
    })
    .await
}
