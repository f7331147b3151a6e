// The C++ side of python/tests/test_bitwise.py: for every instance of the constrained
// solver's reference data (tests/solve/constrained_reference.txt), the results of
// solve_range_space, solve_constrained and force_closure on the grasp type the Python module
// uses (Grasp<Dynamic, Model, double, 64>), printed as hexadecimal floats so that the test can
// compare them with the Python results bit for bit.
//   reference_results <constrained_reference.txt>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <grip/grip.hpp>

namespace {

template <class Model>
void run(const std::vector<grip::Contact<double>>& contacts, const grip::Wrench<double>& w) {
  grip::Grasp<grip::Dynamic, Model, double, 64> g;
  for (const auto& c : contacts)
    if (g.add(c) != grip::Status::Ok) {
      std::printf("invalid\n");
      return;
    }
  const auto print = [](const char* tag, int status, const Eigen::VectorXd& x) {
    std::printf(" %s %d", tag, status);
    for (Eigen::Index i = 0; i < x.size(); ++i) std::printf(" %a", x(i));
  };
  const auto rs = grip::solve_range_space(g, w);
  print("rs", static_cast<int>(rs.status), rs.forces);
  const auto cs = grip::solve_constrained(g, w);
  print("cs", static_cast<int>(cs.status), cs.forces);
  print("cert", 0, cs.certificate);
  const auto fc = grip::force_closure(g);
  print("fc", static_cast<int>(fc.status), Eigen::VectorXd::Constant(1, fc.margin));
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  std::ifstream in(argv[1]);
  std::string line, tag, model;
  std::vector<grip::Contact<double>> contacts;
  grip::Wrench<double> w = grip::Wrench<double>::Zero();
  auto flush = [&] {
    if (model.empty()) return;
    if (model == "H") run<grip::HardFinger>(contacts, w);
    if (model == "S") run<grip::SoftFinger>(contacts, w);
    if (model == "F") run<grip::FrictionlessPoint>(contacts, w);
  };
  while (std::getline(in, line)) {
    std::istringstream s(line);
    if (!(s >> tag) || tag[0] == '#') continue;
    if (tag == "instance") {
      flush();
      int k = 0;
      s >> k >> model;
      contacts.clear();
    } else if (tag == "w") {
      for (int i = 0; i < 6; ++i) s >> w(i);
    } else if (tag == "c") {
      grip::Contact<double> c;
      s >> c.position.x() >> c.position.y() >> c.position.z() >> c.normal.x() >> c.normal.y() >> c.normal.z() >>
          c.friction >> c.torsional_friction >> c.squeeze >> c.weight;
      double bound = -1;
      if (s >> bound && bound > 0) c.max_normal_force = bound;  // bounded instances: -1 for none
      contacts.push_back(c);
    }
  }
  flush();
  return 0;
}
