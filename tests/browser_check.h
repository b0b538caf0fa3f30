// Opening a `brdf demo` report in headless Chromium (report_browser_test.cpp).
#pragma once

#include <string>

namespace brdf {

// Loads REPORT_DIR/report.html in headless Chromium and expects every image to decode, the
// report's title, at least 10 images and no network references.
void ExpectReportLoadsInBrowser(const std::string& report_dir);

}  // namespace brdf
