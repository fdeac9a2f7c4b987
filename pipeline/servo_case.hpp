#pragma once
// The servo feed drives' contour error of a job (machine/servo, docs/feed-drives.md): the job digitized as
// `digitize` does, its steps at their exact times as the reference of the radial and angular servo axes.
#include "job/job.hpp"
#include "machine/servo/contour.hpp"

namespace polarcam {

// The reference (r in m, theta in rad) sampled at T. InputError naming the job for a sand-table arm (its radial
// motor's position is not the tool's radius) or a path the digitizer refuses.
servo::Reference job_servo_reference(const Job& job, double T);

}  // namespace polarcam
