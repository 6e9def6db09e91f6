#include "core/mechanisms/described/joint_grid.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/mechanisms/described/chain.h"

namespace linkscape::described::joint_grid {

using namespace internal;

double allot(std::vector<Freedom>& freedoms, double budget) {
  const auto weight = [](const Freedom& j) { return (j.hi - j.lo) * j.lever; };
  double product = 1;
  for (const Freedom& j : freedoms) product *= std::max(weight(j), 1e-300);
  const double per = std::pow(product / budget, 1.0 / double(freedoms.size()));
  double margin = 0;
  for (Freedom& j : freedoms) {
    j.count = std::clamp(int(std::ceil(weight(j) / per)), 1, int(budget));
    margin += j.half_step() * j.lever;
  }
  return margin;
}

Eigen::Matrix3d basis_along(const Eigen::Vector3d& u) {
  Eigen::Matrix3d b;
  b.col(0) = u;
  b.col(1) = u.unitOrthogonal();
  b.col(2) = u.cross(b.col(1));
  return b;
}

Frames frames_of(const Leg& leg, const std::vector<Freedom>& freedoms, const LegState& seed) {
  Frames f;
  Eigen::Isometry3d acc = leg.base;
  int frame = 0, sphere = 0;
  std::size_t next = 0;
  for (std::size_t i = 0; i < leg.steps.size(); ++i) {
    const Step& step = leg.steps[i];
    f.frame_of_step.push_back(frame);
    f.offset.push_back(acc);
    sphere += step.kind == Step::Kind::Spherical;
    if (next < freedoms.size() && freedoms[next].step == int(i)) {
      f.lead.push_back(acc);
      acc.setIdentity();
      ++frame;
      while (next < freedoms.size() && freedoms[next].step == int(i)) ++next;  // a ball's two dimensions
      continue;
    }
    switch (step.kind) {
      case Step::Kind::Fixed: acc = acc * step.transform; break;
      case Step::Kind::Revolute: acc.rotate(Eigen::AngleAxisd(seed.values(step.variable), step.axis)); break;
      case Step::Kind::Prismatic: acc.translate(step.axis * seed.values(step.variable)); break;
      case Step::Kind::Spherical: acc.rotate(seed.spheres[std::size_t(sphere - 1)]); break;
    }
  }
  f.tail = acc;
  return f;
}

Samples walk_samples(const Leg& leg, const std::vector<Freedom>& freedoms, const Frames& f) {
  const std::size_t k = freedoms.size();
  // Per motion: its first dimension and, per value (a ball's per pair of
  // values, the azimuth fastest), its lead times its motion.
  std::vector<std::size_t> motion_of(k), first;
  std::vector<std::vector<Eigen::Isometry3d>> moved;
  std::size_t total = 1;
  for (std::size_t j = 0; j < k; ++j) {
    total *= std::size_t(freedoms[j].count);
    if (freedoms[j].kind == Freedom::Kind::Azimuth) {
      motion_of[j] = motion_of[j - 1];
      continue;
    }
    motion_of[j] = moved.size();
    first.push_back(j);
    const std::size_t m = moved.size();
    const Step& step = leg.steps[std::size_t(freedoms[j].step)];
    moved.emplace_back();
    for (int i = 0; i < freedoms[j].count; ++i) {
      if (freedoms[j].kind == Freedom::Kind::Polar) {
        // The link after the ball (the tail: a ball is the last motion)
        // turned from its direction as written to the sampled direction.
        const Eigen::Vector3d link = f.tail.translation().normalized();
        const Eigen::Matrix3d written = basis_along(link);
        const double polar = freedoms[j].value(i);
        for (int az = 0; az < freedoms[j + 1].count; ++az) {
          const double azimuth = freedoms[j + 1].value(az);
          const Eigen::Vector3d d = written * Eigen::Vector3d(std::cos(polar), std::sin(polar) * std::cos(azimuth),
                                                              std::sin(polar) * std::sin(azimuth));
          Eigen::Isometry3d mm = f.lead[m];
          mm.linear() = mm.linear() * (basis_along(d) * written.transpose());
          moved[m].push_back(mm);
        }
        continue;
      }
      Eigen::Isometry3d mm = f.lead[m];
      if (freedoms[j].kind == Freedom::Kind::Slide) mm.translate(step.axis * freedoms[j].value(i));
      else mm.rotate(Eigen::AngleAxisd(freedoms[j].value(i), step.axis));
      moved[m].push_back(mm);
    }
  }
  const std::size_t motions = moved.size(), rules = leg.rules.size();
  Samples out;
  out.ends.resize(total);
  out.signs.resize(total * rules);
  std::array<Eigen::Isometry3d, 4> frame;
  frame[0].setIdentity();
  std::array<int, 3> at{0, 0, 0};
  std::size_t changed = 0;  // the first dimension whose value changed
  for (std::size_t index = 0; index < total; ++index) {
    for (std::size_t m = motion_of[std::min(changed, k - 1)]; m < motions; ++m) {
      const std::size_t j = first[m];
      const std::size_t value = freedoms[j].kind == Freedom::Kind::Polar
                                    ? std::size_t(at[j]) * std::size_t(freedoms[j + 1].count) + std::size_t(at[j + 1])
                                    : std::size_t(at[j]);
      frame[m + 1] = frame[m] * moved[m][value];
    }
    const Eigen::Vector3d end = frame[motions] * f.tail.translation();
    out.ends[index] = end;
    const auto centre = [&](int step) -> Eigen::Vector3d {
      return step == -2 ? end : frame[std::size_t(f.frame_of_step[std::size_t(step)])] * f.offset[std::size_t(step)].translation();
    };
    const auto axis = [&](int step) -> Eigen::Vector3d {
      return frame[std::size_t(f.frame_of_step[std::size_t(step)])].linear() *
             (f.offset[std::size_t(step)].linear() * leg.steps[std::size_t(step)].axis);
    };
    for (std::size_t r = 0; r < rules; ++r) {
      const BranchRule& rule = leg.rules[r];
      double value = 0;
      if (rule.kind != BranchRule::Kind::Angle) value = rule_value_from(rule, centre, axis);
      else
        for (std::size_t j = 0; j < k; ++j)
          if (freedoms[j].step == rule.steps[0]) value = sine_sign(freedoms[j].value(at[j]));
      out.signs[index * rules + r] = std::int8_t(value > 0 ? 1 : value < 0 ? -1 : 0);
    }
    // The next sample: the last dimension fastest.
    changed = k;
    while (changed > 0) {
      --changed;
      if (++at[changed] < freedoms[changed].count) break;
      at[changed] = 0;
    }
  }
  return out;
}

EndFreedoms end_freedoms(const Leg& leg, const std::vector<Actuator>& actuators, bool planar, bool within_travel) {
  EndFreedoms out;
  const auto length = [&](const Eigen::Vector3d& v) { return planar ? v.head<2>().norm() : v.norm(); };
  const auto fail = [&](std::string why) {
    out.freedoms.clear();
    out.why_not = std::move(why);
    return out;
  };
  int& last = out.last;
  for (std::size_t i = 0; i < leg.steps.size(); ++i) {
    const Step& step = leg.steps[i];
    if ((step.kind == Step::Kind::Fixed && length(step.transform.translation()) > 0) ||
        step.kind == Step::Kind::Prismatic)
      last = int(i);
  }
  // A slide has a range only as an actuator with a travel, and only within it.
  for (int i = 0; i <= last; ++i) {
    const Step& step = leg.steps[std::size_t(i)];
    if (step.kind != Step::Kind::Prismatic) continue;
    if (!(step.actuator >= 0 && actuators[std::size_t(step.actuator)].limited))
      return fail("a slide without travel moves its end");
    if (!within_travel) return fail("a slide moves its end, beyond its travel too");
  }
  for (int i = 0; i <= last; ++i) {
    const Step& step = leg.steps[std::size_t(i)];
    if (step.kind == Step::Kind::Fixed) continue;
    if (out.ball >= 0 || (step.kind == Step::Kind::Spherical && planar))
      return fail(planar ? "a spherical joint in a planar device" : "a spherical joint moves its end before another joint");
    const Actuator* act = step.actuator >= 0 ? &actuators[std::size_t(step.actuator)] : nullptr;
    // Its lever: what the links after it reach at most.
    double lever = step.kind == Step::Kind::Prismatic ? length(step.axis) : 0.0;
    for (int after = i + 1; after <= last && step.kind != Step::Kind::Prismatic; ++after) {
      const Step& s = leg.steps[std::size_t(after)];
      if (s.kind == Step::Kind::Fixed) lever += length(s.transform.translation());
      if (s.kind == Step::Kind::Prismatic) {
        const Range& r = actuators[std::size_t(s.actuator)].range;
        lever += length(s.axis) * std::max(std::abs(r.lo), std::abs(r.hi));
      }
    }
    if (step.kind == Step::Kind::Spherical) {
      out.ball = i;
      out.freedoms.push_back({Freedom::Kind::Polar, i, lever, 0.0, kPi, false});
      out.freedoms.push_back({Freedom::Kind::Azimuth, i, lever, -kPi, kPi, true});
      continue;
    }
    const bool sliding = step.kind == Step::Kind::Prismatic;
    const bool limited = act && act->limited && (within_travel || sliding);
    out.freedoms.push_back({sliding ? Freedom::Kind::Slide : Freedom::Kind::Turn, i, lever,
                            limited ? act->range.lo : -kPi, limited ? act->range.hi : kPi, !limited});
  }
  if (out.freedoms.empty()) return fail("no joint moves its end");
  return out;
}

std::vector<std::uint64_t> combinations_of(const Leg& leg, const std::vector<Freedom>& freedoms, const Samples& samples,
                                           int last, int ball, const Eigen::Vector3d* turned_about) {
  // Which rules a sample tells: an angle of a revolute it samples; a centre
  // the ball's spin does not move (not one between the ball and the end);
  // an axis that no joint turns that it does not sample in full (a ball's
  // spin, a joint after the last link).
  int turned_from = ball >= 0 ? ball + 1 : int(leg.steps.size());
  for (int i = last + 1; i < int(leg.steps.size()); ++i)
    if (leg.steps[std::size_t(i)].kind != Step::Kind::Fixed) turned_from = std::min(turned_from, i + 1);
  const auto centre_told = [&](int step) { return step == -2 || step > last || ball < 0 || step <= ball; };
  const std::size_t rules = leg.rules.size();
  std::vector<bool> told(rules, true);
  for (std::size_t r = 0; r < rules; ++r) {
    const BranchRule& rule = leg.rules[r];
    if (rule.kind == BranchRule::Kind::Angle)
      told[r] = std::any_of(freedoms.begin(), freedoms.end(), [&](const Freedom& j) {
        return j.step == rule.steps[0] && j.kind == Freedom::Kind::Turn;
      });
    if (rule.kind == BranchRule::Kind::Along)
      told[r] = centre_told(rule.steps[0]) && centre_told(rule.steps[1]) &&
                (!turned_about || rule.direction.cross(*turned_about).norm() < 1e-12);
    if (rule.kind == BranchRule::Kind::Triple)
      told[r] = rule.steps[0] < turned_from &&
                std::all_of(rule.steps.begin(), rule.steps.end(), [&](int step) { return centre_told(step); });
  }
  // Where a rule's sign differs between two neighbouring samples its zero
  // passes between them: they and every sample next to them (diagonally
  // too) stand for assemblies of either sign. The samples next to a ball's
  // poles are all neighbours of one another.
  const std::size_t k = freedoms.size(), total = samples.ends.size();
  std::array<std::size_t, 3> strides{1, 1, 1};  // the last dimension fastest
  for (std::size_t j = k - 1; j > 0; --j) strides[j - 1] = strides[j] * std::size_t(freedoms[j].count);
  // Calls pair(a, b) for each two samples next to each other along dimension j.
  const auto for_each_pair = [&](std::size_t j, auto&& pair) {
    const std::size_t count = std::size_t(freedoms[j].count), stride = strides[j], block = stride * count;
    const std::size_t pairs = freedoms[j].wraps && count > 2 ? count : count - 1;
    for (std::size_t outer = 0; outer < total; outer += block)
      for (std::size_t a = 0; a < pairs; ++a)
        for (std::size_t inner = 0; inner < stride; ++inner)
          pair(outer + a * stride + inner, outer + (a + 1) % count * stride + inner);
  };
  const auto sign = [&](std::size_t sample, std::size_t r) { return samples.signs[sample * rules + r]; };
  std::vector<std::uint8_t> near_zero(total * rules, 0);
  const auto mark = [&](std::size_t sample, std::size_t r) { near_zero[sample * rules + r] = 1; };
  for (std::size_t j = 0; j < k; ++j)
    for_each_pair(j, [&](std::size_t a, std::size_t b) {
      for (std::size_t r = 0; r < rules; ++r)
        if (sign(a, r) != sign(b, r)) mark(a, r), mark(b, r);
    });
  // A ball is the last motion: its polar angle the second last dimension.
  if (ball >= 0) {
    const std::size_t polar = k - 2, azimuths = std::size_t(freedoms[k - 1].count);
    for (std::size_t row = 0; row < total; row += azimuths) {
      const int at = int(row / azimuths % std::size_t(freedoms[polar].count));
      if (at != 0 && at + 1 != freedoms[polar].count) continue;
      for (std::size_t r = 0; r < rules; ++r) {
        bool differs = false;
        for (std::size_t az = 1; az < azimuths; ++az) differs = differs || sign(row + az, r) != sign(row, r);
        for (std::size_t az = 0; az < azimuths && differs; ++az) mark(row + az, r);
      }
    }
  }
  // Spread by one sample along each dimension in turn: to the diagonal
  // neighbours too.
  for (std::size_t j = 0; j < k; ++j) {
    const std::vector<std::uint8_t> before = near_zero;
    for_each_pair(j, [&](std::size_t a, std::size_t b) {
      for (std::size_t r = 0; r < rules; ++r) {
        near_zero[a * rules + r] |= before[b * rules + r];
        near_zero[b * rules + r] |= before[a * rules + r];
      }
    });
  }
  std::vector<std::uint8_t> both(total * rules, 0);
  for (std::size_t index = 0; index < total; ++index)
    for (std::size_t r = 0; r < rules; ++r)
      both[index * rules + r] = !told[r] || samples.signs[index * rules + r] == 0 || near_zero[index * rules + r];
  const int combos = 1 << free_rules_of(leg);
  std::vector<std::uint64_t> out(total, 0);
  for (std::size_t index = 0; index < total; ++index) {
    // The combinations its signs allow: a combination's bit b set where its
    // free rule b is negative.
    int negative = 0, positive = 0, bit = 0;
    bool off_design = false;
    for (std::size_t r = 0; r < rules; ++r) {
      const BranchRule& rule = leg.rules[r];
      const int free_bit = rule.free_index >= 0 ? bit++ : -1;
      if (both[index * rules + r]) continue;
      const int s = sign(index, r);
      if (free_bit < 0) off_design = off_design || s != rule.fixed_sign;
      else (s < 0 ? negative : positive) |= 1 << free_bit;
    }
    for (int combo = 0; combo < combos && !off_design; ++combo)
      if ((combo & negative) == negative && (combo & positive) == 0) out[index] |= std::uint64_t(1) << combo;
  }
  return out;
}

}  // namespace linkscape::described::joint_grid
