// The optimiser of `arttrack tune` (tuning.h): NLopt's derivative-free
// methods over the unit box, with a budget of calls and a fixed seed.
#include <nlopt.hpp>

#include <algorithm>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "arttrack/sim/tuning.h"
#include "arttrack/tracker/error.h"

namespace arttrack::sim {

// ---- optimiser ----

namespace {

// Each optimiser: its enum, its name on the command line, NLopt's algorithm.
struct OptimizerInfo {
  Optimizer optimizer;
  const char* name;
  nlopt::algorithm algorithm;
};
constexpr OptimizerInfo kOptimizers[] = {
    {Optimizer::kBobyqa, "bobyqa", nlopt::LN_BOBYQA},
    {Optimizer::kCobyla, "cobyla", nlopt::LN_COBYLA},
    {Optimizer::kNelderMead, "neldermead", nlopt::LN_NELDERMEAD},
    {Optimizer::kDirect, "direct", nlopt::GN_DIRECT_L}};

const OptimizerInfo& info(Optimizer optimizer) {
  for (const OptimizerInfo& i : kOptimizers)
    if (i.optimizer == optimizer) return i;
  return kOptimizers[0];
}

}  // namespace

Optimizer parse_optimizer(const std::string& name) {
  for (const OptimizerInfo& i : kOptimizers)
    if (name == i.name) return i.optimizer;
  throw InputError("--optimizer '" + name + "': expected bobyqa, cobyla, neldermead or direct");
}

const char* optimizer_name(Optimizer o) { return info(o).name; }

namespace {

struct SearchContext {
  const std::function<double(const std::vector<double>&)>* f = nullptr;
  int budget = 0;
  int calls = 0;
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> best_u;
  std::exception_ptr error;
  bool budget_spent = false;
};

double nlopt_objective(unsigned n, const double* x, double* /*grad*/, void* data) {
  auto* ctx = static_cast<SearchContext*>(data);
  if (ctx->calls >= ctx->budget) {
    ctx->budget_spent = true;
    throw nlopt::forced_stop();
  }
  std::vector<double> u(x, x + n);
  for (double& v : u) v = std::clamp(v, 0.0, 1.0);
  double value = 0;
  try {
    value = (*ctx->f)(u);
  } catch (...) {
    ctx->error = std::current_exception();
    throw nlopt::forced_stop();
  }
  ++ctx->calls;
  if (value < ctx->best || ctx->best_u.empty()) {
    ctx->best = value;
    ctx->best_u = u;
  }
  return value;
}

// Why NLopt stopped, in words.
std::string stop_text(nlopt::result r) {
  static const std::pair<nlopt::result, const char*> kTexts[] = {
      {nlopt::SUCCESS, "converged"},
      {nlopt::STOPVAL_REACHED, "target value reached"},
      {nlopt::FTOL_REACHED, "objective changes below tolerance"},
      {nlopt::XTOL_REACHED, "steps below tolerance"},
      {nlopt::MAXEVAL_REACHED, "budget spent"},
      {nlopt::MAXTIME_REACHED, "time limit"}};
  for (const auto& [result, text] : kTexts)
    if (r == result) return text;
  return "stopped (code " + std::to_string(int(r)) + ")";
}

}  // namespace

OptimizerResult minimize_unit_box(const std::function<double(const std::vector<double>&)>& f,
                                  const std::vector<double>& u0, Optimizer optimizer, int budget,
                                  double tolerance) {
  const unsigned n = unsigned(u0.size());
  if (n == 0) throw InputError("tune: no parameters to optimise");
  if (budget < 1) throw InputError("--budget must be >= 1");
  const nlopt::algorithm alg = info(optimizer).algorithm;
  nlopt::srand(20170101);  // deterministic, whatever the algorithm
  nlopt::opt opt(alg, n);
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_maxeval(budget);
  opt.set_xtol_abs(tolerance);
  if (optimizer != Optimizer::kDirect) opt.set_initial_step(0.25);

  SearchContext ctx;
  ctx.f = &f;
  ctx.budget = budget;
  opt.set_min_objective(nlopt_objective, &ctx);
  std::vector<double> x(n);
  for (unsigned i = 0; i < n; ++i) x[i] = std::clamp(u0[i], 0.0, 1.0);
  OptimizerResult result;
  double value = 0;
  try {
    result.stop = stop_text(opt.optimize(x, value));
  } catch (const nlopt::forced_stop&) {
    if (ctx.error) std::rethrow_exception(ctx.error);
    result.stop = ctx.budget_spent ? "budget spent" : "forced stop";
  } catch (const nlopt::roundoff_limited&) {
    result.stop = "roundoff limited";
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("optimiser: invalid arguments: ") + e.what());
  } catch (const std::runtime_error& e) {
    if (ctx.error) std::rethrow_exception(ctx.error);
    result.stop = std::string("optimiser failure: ") + e.what();
  }
  if (ctx.error) std::rethrow_exception(ctx.error);
  result.evaluations = ctx.calls;
  result.u = ctx.best_u.empty() ? x : ctx.best_u;
  result.value = ctx.best;
  return result;
}

}  // namespace arttrack::sim
