#include "core/noise.h"

namespace colony {

std::vector<AttributeDoc> NoiseModel::Attributes(bool with_drop) {
  std::vector<AttributeDoc> a = {
      {"noise", "none, gaussian, uniform", "none", "noise added to each reading"},
      {"noise_std_dev", "a number >= 0", "0", "standard deviation of gaussian noise"},
      {"noise_range", "\"min,max\"", "0,0", "bounds of uniform noise"},
  };
  if (with_drop)
    a.push_back({"drop_probability", "a number in [0, 1]", "0",
                 "probability that a reading is lost (reads 0)"});
  return a;
}

NoiseModel NoiseModel::Read(const ConfigNode& node) {
  NoiseModel m;
  const std::string kind = node.GetChoice("noise", {"none", "gaussian", "uniform"}, "none");
  m.kind = kind == "gaussian" ? Kind::kGaussian : kind == "uniform" ? Kind::kUniform : Kind::kNone;
  m.std_dev = node.GetDouble("noise_std_dev", 0, Range::NonNegative());
  if (node.Has("noise_range")) {
    const std::string raw = node.GetString("noise_range", "");
    const auto parts = SplitList(raw);
    double a = 0, b = 0;
    if (parts.size() != 2 || !ParseFiniteDouble(parts[0], a) || !ParseFiniteDouble(parts[1], b) ||
        a > b) {
      node.Error("noise_range", raw,
                 "'" + raw + "' is not accepted; accepted: \"min,max\" with min <= max");
    } else {
      m.min = a;
      m.max = b;
    }
  }
  m.drop_probability = node.GetDouble("drop_probability", 0, Range::Between(0, 1));
  if (m.kind == Kind::kGaussian && !node.Has("noise_std_dev")) {
    node.Error("noise_std_dev", "", "required when noise=\"gaussian\"");
  }
  if (m.kind == Kind::kUniform && !node.Has("noise_range")) {
    node.Error("noise_range", "", "required when noise=\"uniform\"");
  }
  return m;
}

}  // namespace colony
