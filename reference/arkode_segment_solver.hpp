#pragma once
/// \file arkode_segment_solver.hpp
/// ARKODE's ERKStep with the Fehlberg 13-7-8 table as the segment loop drives it
/// (reference/arkode_solver.cpp has the method and its choices): stepped one step at a time,
/// outputs from the order-8 continuous extension, and the location of the switches a step
/// meets (reference/arkode_switch_location.cpp). Internal to reference/.
#include <arkode/arkode.h>
#include <arkode/arkode_erkstep.h>

#include <span>
#include <string>
#include <vector>

#include "reference/continuous_extension.hpp"
#include "reference/integral_weights.hpp"
#include "reference/ode_form.hpp"
#include "reference/reference_solver.hpp"
#include "reference/sundials_handle.hpp"
#include "reference/sundials_ode_callbacks.hpp"
#include "reference/sundials_segment_driver.hpp"
#include "reference/switching_predictor.hpp"

namespace flexref::reference::arkode_detail {

namespace sun = sundials;

/// ARKODE's factor on the step the stability hook returns (its default; it refuses 1).
inline constexpr double kCflFraction = 0.5;

/// ARKODE's bound on the growth of the step from one step to the next (its default).
inline constexpr double kMaxGrowth = 20.0;

/// approach_switch: the most error-controlled approaches to one switch, and the shortest
/// distance (in time resolutions, 4 ulp) from the step's start to the switch worth one.
inline constexpr int kMaxApproaches = 16;
inline constexpr double kApproachResolutions = 64.0;

/// ERKStep with the Fehlberg 13-7-8 table on the ODE form.
sun::ErkStepMemory make_fehlberg(N_Vector y, SUNContext context, sun::OdeCallbackData& data);

/// ARKODE ERKStep on the ODE form, driven segment by segment by integrate_segments.
class ArkodeSegmentSolver final : public sun::SegmentSolver {
 public:
  /// `stabilization`: Baumgarte's rate of the ODE form (ERKStep cannot project).
  ArkodeSegmentSolver(const core::Model& model, const SolverOptions& options, double stabilization);

  void start_segment(const sun::Segment& segment, const core::State& state,
                     std::span<const double> integrals) override;

  Advance advance(double tout, double next) override;

  void restart_at_root(double t, const sun::Segment& segment) override;

  void unpack(double t, core::State& state) const override;
  void accept_output(double t, const core::State& state) override;
  void integrals(std::span<double> out) const override;

  void add_counters(SolverStats& stats) const override;

  double current_time(double fallback) const override { return std::isnan(t_) ? fallback : t_; }
  long current_steps() const override { return accepted_steps_ - counted_.steps; }
  std::string failure_message(const std::string& what) const override;

 private:
  sun::Vector make() { return sun::make_vector(form_.size(), context_.get()); }

  /// ARKExpStabFn: SwitchingPredictor's cap on a step from (t, y) over the longest step ARKODE
  /// may try next, kMaxGrowth times its current one (0: no cap). ARKODE calls it before every
  /// step attempt.
  static int switching_cap(N_Vector y, sunrealtype t, sunrealtype* h_stab, void* user_data);

  static double slack(double t);

  /// A new step sequence from y_ at t0 up to the stop time `stop`.
  void restart(double t0, double stop);

  /// Some switching function is not positive at (t, y), a step's start; keeps them in g_start_.
  bool contact_engaged(double t, N_Vector y);

  /// After locate_event found a switch inside the step from (t0, y_start_): that step was
  /// accepted on an error estimate over both branches, and the state at the switch came from one
  /// unchecked Fehlberg step onto the non-smooth end of the branch (a Hunt–Crossley force
  /// ∝ δ^1.5 leaves the solution only C³ at a release: that step's error is ~h^3.5, not the
  /// method's h⁹). Measured on bouncing_ball (1 s, 2 impacts) with that step kept: an energy
  /// balance of 1.2e-5, 2.8e-6, 2.5e-7 J at rtol 1e-8, 1e-10, 1e-12, i.e. ~6× per 100×. So the step
  /// is discarded and the integration restarts from t0 under ARKODE's error control, with a stop
  /// (tstop) at the switch's near side, where cross_switch takes
  /// the short located step across; no accepted step then straddles the switch (as in
  /// precision/switched_integration.hpp). An approach whose own step meets the switch early is
  /// approached again from that step's start, so each retry starts closer; at most
  /// kMaxApproaches per switch, after which the located step is kept as before. Returns whether
  /// an approach started.
  bool approach_switch(double t0);

  /// The approach reached the near side of the switch (y_ at approach_end_): the short step
  /// across it, lengthened (doubling) until its end is on the new side. Leaves y_ past the switch,
  /// the near side in y_near_, and returns true; false when no such step reaches the switch (the
  /// trajectory meets it later): the integration then goes on from the near side towards the
  /// segment end, and ARKODE's root finding sees the switch again.
  bool cross_switch();

  /// The switch locate_event just found is a release: a function not positive at the step's
  /// start (g_start_) is positive past the switch (g_, its values at y_). An onset is not
  /// approached: its state comes from the located step as before (an onset's force, ∝ δⁿ from
  /// zero or c δ̇ for the damped linear law, is on the far side of the step's end, where the
  /// approach found nothing to gain on bouncing_ball and tube_support_impact and, for the damped
  /// linear law's jump, lost accuracy on hinged_spinner_strike: 4e-4 m at rtol 1e-8).
  bool is_release() const;

  /// Some switching function at (t, y) is on another side than at the last step's start
  /// (g_start_).
  bool switch_changed(double t, N_Vector y);

  /// The event time, to a few ulp, inside the step from (t0, y_start_) whose switching
  /// functions changed side: bisection on the length of one Fehlberg step from its start (the
  /// step's own solution, as accurate as the step), from ARKODE's bracket (its estimate t_root,
  /// from its degree-5 interpolant, placed roots up to 2e-5 s off on bouncing_ball) and the
  /// step's end. A trial counts as past the switch when its end or any of its stages is on
  /// another side than the start (a stage near the end lies a local error off the trajectory,
  /// and a damped penalty law jumps at an onset, F = c δ̇ at δ = 0: one stage there added
  /// ~b_i h c δ̇ / m to the step, 6e-5 m on hinged_spinner_strike at every tolerance). The state
  /// past the switch is one clean step to the bracket's near end, then one across it, lengthened
  /// (doubling, up to 1024 brackets) until its end is past; when it is not, the bisection starts
  /// again from that near end with short, accurate trials. Leaves y_ just past the zero, on the
  /// new side, and the near side's state in y_near_ (the continuous extension's left limit), and
  /// returns its time.
  double locate_event(double t0, double t_root);

  /// The step-doubling test of the step (t0, y_start_) → (t1, y_): two Fehlberg steps of half
  /// its length agree with it in ARKODE's WRMS error norm. On failure retry_step_ is the
  /// order-8 controller's proposal, h (0.9 / error)^(1/8) within [h/5, h/2].
  bool halves_agree(double t0, double t1);

  /// y_end_ = the state at tout inside or at the end of the last step [step_start_, t_]: the
  /// step's own end value there; inside, when tout is the step's only output (the next request
  /// lies beyond the step's end), one Fehlberg step from the step's start onto it, else its
  /// continuous extension (fitted once per step). Both are of the method's order.
  void output_at(double tout, double next);

  /// The order-8 continuous extension of [step_start_, t_]: the ends, two interior nodes by
  /// fixed steps of h/3 and 2h/3 from the start, and the derivative at each node.
  void fit_extension();

  /// out = one Fehlberg 13-7-8 step of length h from (t0, y0) (out may not alias y0).
  void fixed_step(double t0, N_Vector y0, double h, N_Vector out);

  SolverOptions options_;
  OdeForm form_;
  /// The works in y as increments since the last (re)start (reference/integral_weights.hpp).
  IntegralBase works_{{form_.work_index(), form_.integral_count()}};
  sun::OdeCallbackData data_;
  sun::Context context_;
  sun::Vector y_;                                    ///< the solution at t_
  sun::Vector y_start_, y_end_, y_node1_, y_node2_;  ///< step start, output, interior nodes
  sun::Vector f_start_, f_end_, f_node1_, f_node2_;
  sun::Vector weights_;
  sun::Vector y_probe_, f_probe_;  ///< the switching cap's evaluations
  /// locate_event: the trials' start, and the near end of the located bracket.
  sun::Vector y_from_, y_near_;
  /// approach_switch: the located time past the switch, the near side's time the approach stops
  /// at, and how many approaches this switch has had.
  double event_time_ = 0.0;
  double approach_end_ = 0.0;
  bool approaching_ = false;
  int approaches_ = 0;
  bool ended_at_event_ = false;  ///< the last accepted step ended just past a switch
  double near_time_ = 0.0;       ///< the time of y_near_
  SwitchingPredictor predictor_;
  /// Switching functions: scratch (locate_event, switching_cap) and at a step's start.
  std::vector<double> g_, g_start_;
  ContinuousExtension extension_;
  double t_ = 0.0;           ///< time of y_
  double step_start_ = 0.0;  ///< start of the last accepted step
  double stop_ = 0.0;        ///< the segment's end (tstop)
  double retry_step_ = 0.0;
  bool fitted_ = false;        ///< extension_ fits [step_start_, t_]
  bool output_ready_ = false;  ///< y_end_ holds the last output (else y_ is the state)
  bool root_pending_ = false;  ///< y_, t_ are a located event not yet returned
  long accepted_steps_ = 0;
  long restart_steps_ = 0;       ///< accepted_steps_ at the last restart
  long rejected_steps_ = 0;      ///< steps discarded by the contact step-doubling test
  mutable SolverStats counted_;  ///< counters already added to the run
  // Declared last so that they are freed first (as in SUNDIALS' examples).
  sun::ErkStepMemory erk_;
  sun::ErkStepMemory restep_;
};

}  // namespace flexref::reference::arkode_detail
