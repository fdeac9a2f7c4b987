#include "pipeline/servo_case.hpp"

#include "cam/error.hpp"
#include "machine/servo/step_reference.hpp"
#include "pipeline/job_tape.hpp"

namespace polarcam {

servo::Reference job_servo_reference(const Job& job, double T) {
  if (job.machine.coupling != 0.0)
    throw InputError("the servo model takes r and theta as its axes: a sand-table arm (coupling) is not one", job.file);
  const double res[2] = {job.machine.grid.dr, job.machine.grid.dtheta};
  servo::StepSampler sampler(res, 0, 0);
  const DigitizedJob d = digitize_job(job, &sampler);
  sampler.begin(d.result.start_n, d.result.start_m);
  return in_file(job.file, [&] { return sampler.sample(T); });
}

}  // namespace polarcam
