// Small fixed-size types shared by every library. Templated on the scalar so that one model
// definition evaluates with double and with ceres::Jet (STYLE rule 3).
#pragma once

#include <Eigen/Core>

namespace brdf {

template <typename T>
using Vec3T = Eigen::Matrix<T, 3, 1>;
using Vec3 = Vec3T<double>;

// Linear Rec.709/sRGB RGB triple (DESIGN §1); arithmetic is component-wise.
template <typename T>
using RgbT = Eigen::Array<T, 3, 1>;
using Rgb = RgbT<double>;

}  // namespace brdf
