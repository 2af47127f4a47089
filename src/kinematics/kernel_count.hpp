#pragma once
// The kernel evaluations of the calling thread: how many times forwardKinematics ran on it (alone
// or inside forwardKinematicsAndJacobian) since the thread started. A search counts the kernel
// evaluations of a solve as the difference before and after it, on the thread that ran it; the
// count is the same whichever thread runs a solve, so totals do not depend on the schedule.
namespace armstudy {

long kernelEvaluationsOnThisThread();

}  // namespace armstudy
