#include "io/sweep.hpp"

#include <fmt/format.h>

#include <cctype>
#include <set>

#include "core/errors.hpp"

namespace bakesim {

SweepAxis parse_sweep_axis(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set",
                     "expects KEY.PATH=V1,V2,... (e.g. environment.air_temperature=150,180,210), got '" + text + "'");
  SweepAxis axis{text.substr(0, eq), {}};
  const std::string list = text.substr(eq + 1);
  int depth = 0;
  bool quoted = false;
  std::string value;
  auto push = [&] {
    if (value.empty()) throw InputError("--set " + axis.path, "an empty value in '" + list + "'");
    axis.values.push_back(value);
    value.clear();
  };
  for (std::size_t i = 0; i < list.size(); ++i) {
    const char ch = list[i];
    if (quoted) {
      if (ch == '\\' && i + 1 < list.size()) {  // an escaped character, a quote included
        value += ch;
        value += list[++i];
        continue;
      }
      if (ch == '"') quoted = false;
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == '[' || ch == '{') {
      ++depth;
    } else if (ch == ']' || ch == '}') {
      --depth;
    } else if (ch == ',' && depth == 0) {
      push();
      continue;
    }
    value += ch;
  }
  push();
  if (axis.values.size() > 1000) throw InputError("--set " + axis.path, "more than 1000 values");
  return axis;
}

std::vector<std::string> axis_names(const std::vector<SweepAxis>& axes) {
  auto last_key = [](const std::string& path) {
    std::string key = path.substr(path.rfind('.') == std::string::npos ? 0 : path.rfind('.') + 1);
    return key.substr(0, key.find('['));
  };
  std::vector<std::string> names;
  for (const auto& a : axes) {
    std::size_t same = 0;
    for (const auto& b : axes) same += last_key(b.path) == last_key(a.path);
    names.push_back(same > 1 ? a.path : last_key(a.path));
  }
  return names;
}

std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes, std::size_t max_points) {
  std::size_t count = 1;
  for (const auto& a : axes) {
    count *= a.values.size();
    if (count > max_points)
      throw InputError("--set", fmt::format("the grid has more than {} runs; split the sweep", max_points));
  }
  const std::vector<std::string> names = axis_names(axes);
  const int digits = static_cast<int>(fmt::format("{}", count).size());
  std::vector<SweepPoint> points;
  for (std::size_t n = 0; n < count; ++n) {
    SweepPoint p;
    std::size_t rest = n;
    std::vector<std::size_t> index(axes.size());
    for (std::size_t k = axes.size(); k-- > 0;) {
      index[k] = rest % axes[k].values.size();
      rest /= axes[k].values.size();
    }
    for (std::size_t k = 0; k < axes.size(); ++k) {
      const std::string& v = axes[k].values[index[k]];
      p.sets.push_back(axes[k].path + "=" + v);
      p.values.push_back(v);
      if (axes[k].values.size() > 1) p.label += (p.label.empty() ? "" : ",") + names[k] + "=" + v;
    }
    if (p.label.empty()) p.label = "run";
    // One safe path component: letters, digits and - _ . = kept; the rest (the commas too) become _.
    std::string safe;
    for (const unsigned char ch : p.label)
      safe += std::isalnum(ch) || std::string("-_.=").find(char(ch)) != std::string::npos ? char(ch) : '_';
    if (safe.size() > 120) safe.resize(120);
    p.directory = fmt::format("{:0{}}-{}", n + 1, digits, safe);
    points.push_back(std::move(p));
  }
  return points;
}

}  // namespace bakesim
