// Headless Chromium on a report page, for the tests labelled browser: the DOM it builds
// offline, and whether the screenshot it paints holds charts.
#pragma once

#include <cstddef>
#include <filesystem>
#include <sstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/support/shell.h"

namespace ringtol::testing {

// What Chromium made of a page: the DOM (out) with its log (err: page errors show as
// "CONSOLE" lines, failed fetches as "net::ERR"), then a screenshot 1000 px wide, measured.
struct ChromiumPage {
  ShellOutcome dom;
  ShellOutcome shot;
  double ink = 0.0;          // the share of the screenshot's pixels that are not white
  std::size_t colours = 0;   // distinct colours in the screenshot
  std::size_t svg_count = 0; // <svg elements in the DOM
};

// Renders `page` from a profile in `dir` (the test's own folder, which it may fill).
inline ChromiumPage RenderInChromium(const std::filesystem::path& page, const std::filesystem::path& dir) {
  const auto run = [&](const std::string& command) { return RunShell(command, dir / "chromium_stderr.txt"); };
  const std::string png = (dir / "page.png").string();
  const std::string chromium =
      "timeout 120 chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run "
      "--user-data-dir=" +
      (dir / "chromium-profile").string() + " --enable-logging=stderr --v=0 --window-size=1000,2600 ";
  ChromiumPage out;
  out.dom = run(chromium + "--dump-dom file://" + page.string());
  for (std::size_t at = out.dom.out.find("<svg"); at != std::string::npos; at = out.dom.out.find("<svg", at + 1)) {
    ++out.svg_count;
  }
  out.shot = run(chromium + "--screenshot=" + png + " file://" + page.string());
  if (out.shot.exit_code != 0) return out;
  const ShellOutcome pixels =
      run("/usr/bin/python3 -c \"import sys; from PIL import Image; im = Image.open(sys.argv[1])"
          ".convert('RGB'); px = list(im.getdata()); ink = sum(1 for p in px if p != (255, 255, 255));"
          " print(ink / len(px), len(set(px)))\" " +
          png);
  std::istringstream(pixels.out) >> out.ink >> out.colours;
  return out;
}

// Chromium loaded the page offline without page errors and painted it: many pixels that
// are neither white nor one flat colour.
inline void ExpectPaintedWithoutErrors(const ChromiumPage& shown) {
  using ::testing::HasSubstr;
  using ::testing::Not;
  ASSERT_EQ(shown.dom.exit_code, 0) << shown.dom.err;
  EXPECT_THAT(shown.dom.err, Not(HasSubstr("CONSOLE")));
  EXPECT_THAT(shown.dom.err, Not(HasSubstr("net::ERR")));
  ASSERT_EQ(shown.shot.exit_code, 0) << shown.shot.err;
  EXPECT_GT(shown.ink, 0.03);
  EXPECT_GT(shown.colours, 20u);
}

// Nothing in the page a browser would fetch (the SVG namespace is a name, not a fetch).
inline constexpr const char* kFetches[] = {"<script", "<link", "<img", "<iframe", "src=", "url(", "@import",
                                           "href=\"http"};

}  // namespace ringtol::testing
