// Registration of the `r_test` builtin model with the uncertainty engine's registry
// (engine/apps/uncertainty/model_function.h). The registry sits below this layer, so the command
// line calls register_r_test_model() before it reads a model file. The registered model checks the
// model file (its six input classes and the keys of `builtin:`) when the file is read; the
// evaluation itself is compound (a calibration, several routes, a verification) and runs
// through evaluate_r_test (r_test_evaluation.h), not through the per-trial evaluate().
#pragma once

namespace gearmc::rtest {

// Idempotent; thread-safe (the registry locks).
void register_r_test_model();

}  // namespace gearmc::rtest
