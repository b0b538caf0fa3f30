// CIE colorimetric tables on the 5 nm grid 360..830 nm (95 rows), the grid of CieTables in
// core/colour.h.
//
// Sources (the numbers are the CIE's; the layout here is ours):
//  - Colour matching functions of the CIE 1931 standard colorimetric observer (2 degree):
//    CIE 015:2018 "Colorimetry, 4th ed." and ISO/CIE 11664-1 (formerly CIE S 014-1); the CIE
//    distributes them as the data set CIE_xyz_1931_2deg.csv (CIE 018:2019, DOI
//    10.25039/CIE.DS.xvudnb9b), 1 nm steps, of which these are the rows at multiples of 5 nm.
//    Read from the full-precision copy data/CIE_xyz_1931_2deg.csv in the public repository
//    fderue/chromaticity-diagram, and checked row by row against the CVRL table ciexyz31
//    (www.cvrl.org) as carried in the public sources of Bruneton's precomputed-atmospheric-
//    scattering demo; 400..700 nm also against the CIE 204 spreadsheet values quoted in
//    JSpecView's Visible.java, which are the same numbers rounded to 6 decimals, as printed in
//    CIE 015. Values such as 0.006450001 or 4.999999e-05 are printed that way in the full
//    precision tabulation (artefacts of how it was produced) and are kept verbatim; they
//    differ from the rounded ones by at most 1e-7.
//  - Relative spectral power of CIE standard illuminant D65 (ISO/CIE 11664-2 / CIE S 014-2,
//    normalized to 100 at 560 nm): CIE data set "CIE_std_illum_D65.csv" (DOI
//    10.25039/CIE.DS.hjfjmt59), rows at multiples of 5 nm; read from the copy in the public
//    repository JakeCambium/532nm-and-695nm-dualband-Cary-spectrophotometer-plotting.
//
// Cross-checks made when transcribing (they are also the unit tests in tests/colour_test.cpp):
//  sum ybar * 5 nm = 106.857; ybar(555) = 1 is the maximum; xbar(600) = 1.0622;
//  zbar(445) = 1.7826; D65(560) = 100; and D65's white point summed over 380..780 nm at 5 nm is
//  X = 95.043, Z = 108.880 (Y = 100), i.e. xy = (0.31272, 0.32903) as CIE 015 tabulates.
#include "core/colour.h"

namespace brdf {

// One row of five values per line, labelled with its wavelengths, so the rows can be read against
// the CIE tables.
// clang-format off
// xbar(lambda), CIE 1931 2 degree observer.
const double CieTables::kXBar[CieTables::kCount] = {
    0.0001299, 0.0002321, 0.0004149, 0.0007416, 0.001368,  // 360-380 nm
    0.002236, 0.004243, 0.00765, 0.01431, 0.02319,  // 385-405 nm
    0.04351, 0.07763, 0.13438, 0.21477, 0.2839,  // 410-430 nm
    0.3285, 0.34828, 0.34806, 0.3362, 0.3187,  // 435-455 nm
    0.2908, 0.2511, 0.19536, 0.1421, 0.09564,  // 460-480 nm
    0.05795001, 0.03201, 0.0147, 0.0049, 0.0024,  // 485-505 nm
    0.0093, 0.0291, 0.06327, 0.1096, 0.1655,  // 510-530 nm
    0.2257499, 0.2904, 0.3597, 0.4334499, 0.5120501,  // 535-555 nm
    0.5945, 0.6784, 0.7621, 0.8425, 0.9163,  // 560-580 nm
    0.9786, 1.0263, 1.0567, 1.0622, 1.0456,  // 585-605 nm
    1.0026, 0.9384, 0.8544499, 0.7514, 0.6424,  // 610-630 nm
    0.5419, 0.4479, 0.3608, 0.2835, 0.2187,  // 635-655 nm
    0.1649, 0.1212, 0.0874, 0.0636, 0.04677,  // 660-680 nm
    0.0329, 0.0227, 0.01584, 0.01135916, 0.008110916,  // 685-705 nm
    0.005790346, 0.004109457, 0.002899327, 0.00204919, 0.001439971,  // 710-730 nm
    0.0009999493, 0.0006900786, 0.0004760213, 0.0003323011, 0.0002348261,  // 735-755 nm
    0.0001661505, 0.000117413, 8.307527e-05, 5.870652e-05, 4.150994e-05,  // 760-780 nm
    2.935326e-05, 2.067383e-05, 1.455977e-05, 1.025398e-05, 7.221456e-06,  // 785-805 nm
    5.085868e-06, 3.581652e-06, 2.522525e-06, 1.776509e-06, 1.251141e-06,  // 810-830 nm
};

// ybar(lambda) = V(lambda), the photopic luminous efficiency, peak 1 at 555 nm.
const double CieTables::kYBar[CieTables::kCount] = {
    3.917e-06, 6.965e-06, 1.239e-05, 2.202e-05, 3.9e-05,  // 360-380 nm
    6.4e-05, 0.00012, 0.000217, 0.000396, 0.00064,  // 385-405 nm
    0.00121, 0.00218, 0.004, 0.0073, 0.0116,  // 410-430 nm
    0.01684, 0.023, 0.0298, 0.038, 0.048,  // 435-455 nm
    0.06, 0.0739, 0.09098, 0.1126, 0.13902,  // 460-480 nm
    0.1693, 0.20802, 0.2586, 0.323, 0.4073,  // 485-505 nm
    0.503, 0.6082, 0.71, 0.7932, 0.862,  // 510-530 nm
    0.9148501, 0.954, 0.9803, 0.9949501, 1.0,  // 535-555 nm
    0.995, 0.9786, 0.952, 0.9154, 0.87,  // 560-580 nm
    0.8163, 0.757, 0.6949, 0.631, 0.5668,  // 585-605 nm
    0.503, 0.4412, 0.381, 0.321, 0.265,  // 610-630 nm
    0.217, 0.175, 0.1382, 0.107, 0.0816,  // 635-655 nm
    0.061, 0.04458, 0.032, 0.0232, 0.017,  // 660-680 nm
    0.01192, 0.00821, 0.005723, 0.004102, 0.002929,  // 685-705 nm
    0.002091, 0.001484, 0.001047, 0.00074, 0.00052,  // 710-730 nm
    0.0003611, 0.0002492, 0.0001719, 0.00012, 8.48e-05,  // 735-755 nm
    6e-05, 4.24e-05, 3e-05, 2.12e-05, 1.499e-05,  // 760-780 nm
    1.06e-05, 7.4657e-06, 5.2578e-06, 3.7029e-06, 2.6078e-06,  // 785-805 nm
    1.8366e-06, 1.2934e-06, 9.1093e-07, 6.4153e-07, 4.5181e-07,  // 810-830 nm
};

// zbar(lambda); the CIE tabulates exact zeros from 650 nm on.
const double CieTables::kZBar[CieTables::kCount] = {
    0.0006061, 0.001086, 0.001946, 0.003486, 0.006450001,  // 360-380 nm
    0.01054999, 0.02005001, 0.03621, 0.06785001, 0.1102,  // 385-405 nm
    0.2074, 0.3713, 0.6456, 1.0390501, 1.3856,  // 410-430 nm
    1.62296, 1.74706, 1.7826, 1.77211, 1.7441,  // 435-455 nm
    1.6692, 1.5281, 1.28764, 1.0419, 0.8129501,  // 460-480 nm
    0.6162, 0.46518, 0.3533, 0.272, 0.2123,  // 485-505 nm
    0.1582, 0.1117, 0.07824999, 0.05725001, 0.04216,  // 510-530 nm
    0.02984, 0.0203, 0.0134, 0.008749999, 0.005749999,  // 535-555 nm
    0.0039, 0.002749999, 0.0021, 0.0018, 0.001650001,  // 560-580 nm
    0.0014, 0.0011, 0.001, 0.0008, 0.0006,  // 585-605 nm
    0.00034, 0.00024, 0.00019, 0.0001, 4.999999e-05,  // 610-630 nm
    3e-05, 2e-05, 1e-05, 0.0, 0.0,  // 635-655 nm
    0.0, 0.0, 0.0, 0.0, 0.0,  // 660-680 nm
    0.0, 0.0, 0.0, 0.0, 0.0,  // 685-705 nm
    0.0, 0.0, 0.0, 0.0, 0.0,  // 710-730 nm
    0.0, 0.0, 0.0, 0.0, 0.0,  // 735-755 nm
    0.0, 0.0, 0.0, 0.0, 0.0,  // 760-780 nm
    0.0, 0.0, 0.0, 0.0, 0.0,  // 785-805 nm
    0.0, 0.0, 0.0, 0.0, 0.0,  // 810-830 nm
};

// CIE standard illuminant D65, relative spectral power (100 at 560 nm).
const double CieTables::kD65[CieTables::kCount] = {
    46.6383, 49.3637, 52.0891, 51.0323, 49.9755,  // 360-380 nm
    52.3118, 54.6482, 68.7015, 82.7549, 87.1204,  // 385-405 nm
    91.486, 92.4589, 93.4318, 90.057, 86.6823,  // 410-430 nm
    95.7736, 104.865, 110.936, 117.008, 117.41,  // 435-455 nm
    117.812, 116.336, 114.861, 115.392, 115.923,  // 460-480 nm
    112.367, 108.811, 109.082, 109.354, 108.578,  // 485-505 nm
    107.802, 106.296, 104.79, 106.239, 107.689,  // 510-530 nm
    106.047, 104.405, 104.225, 104.046, 102.023,  // 535-555 nm
    100.0, 98.1671, 96.3342, 96.0611, 95.788,  // 560-580 nm
    92.2368, 88.6856, 89.3459, 90.0062, 89.8026,  // 585-605 nm
    89.5991, 88.6489, 87.6987, 85.4936, 83.2886,  // 610-630 nm
    83.4939, 83.6992, 81.863, 80.0268, 80.1207,  // 635-655 nm
    80.2146, 81.2462, 82.2778, 80.281, 78.2842,  // 660-680 nm
    74.0027, 69.7213, 70.6652, 71.6091, 72.979,  // 685-705 nm
    74.349, 67.9765, 61.604, 65.7448, 69.8856,  // 710-730 nm
    72.4863, 75.087, 69.3398, 63.5927, 55.0054,  // 735-755 nm
    46.4182, 56.6118, 66.8054, 65.0941, 63.3828,  // 760-780 nm
    63.8434, 64.304, 61.8779, 59.4519, 55.7054,  // 785-805 nm
    51.959, 54.6998, 57.4406, 58.8765, 60.3125,  // 810-830 nm
};
// clang-format on

}  // namespace brdf
