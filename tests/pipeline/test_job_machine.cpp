// The example machine file (examples/machines/fahim1983.toml), read by the job's machine-file reader, carries
// Table 5.1 of the thesis as the shared reference data gives it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <variant>

#include "job/job_dynamics.hpp"
#include "tests/reference_data.hpp"

namespace tu_pipeline_test_job_machine {  // the test files of a program compile together (unity build)

using namespace polarcam;
using polarcam::test::read_reference;
using polarcam::test::Reference;

TEST(DynamicsReference, ExampleMachineCarriesTable51) {
  auto ref = read_reference();
  if (!ref) GTEST_SKIP() << "shared reference data not found at " << POLARCAM_SHARED_DIR;
  const Reference& p = *ref;
  const MachineModel m = load_machine_dynamics(std::string(POLARCAM_SOURCE_DIR) + "/examples/machines/fahim1983.toml");
  auto near = [](double got, double want) { EXPECT_NEAR(got, want, 1e-3 * std::abs(want)) << want; };
  near(m.mech.carriage_mass, p.M_c);
  near(m.mech.arm_inertia, p.J_A);
  near(m.mech.arm_friction_torque, p.FfLA);
  near(m.mech.K1, p.K1);
  near(m.mech.K2, p.K2);
  near(m.mech.k_theta, p.k_theta);
  near(m.mech.k_R, p.k_R);
  for (const StepperMotor* sm : {&m.radial, &m.angular}) {
    ASSERT_TRUE(sm->electrical());
    const ElectricalMotor& e = std::get<ElectricalMotor>(sm->model);
    near(e.supply_voltage, p.V_supply);
    near(e.K_V, p.K_V);
    near(e.K_T, p.K_T);
    near(e.R_a, p.R_a);
    near(e.L_a, p.L_a);
    EXPECT_EQ(e.rotor_teeth, p.N_s);
    EXPECT_EQ(e.energisation, Energisation::wave);
  }
}

}  // namespace tu_pipeline_test_job_machine
