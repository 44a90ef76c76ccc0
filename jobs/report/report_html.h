// A campaign report as one self-contained HTML page: no scripts, no network, no files
// beside it; charts are inline SVG (jobs/report/svg_chart.h), styles inline, and a print style
// sheet keeps every chart and table whole on paper. The page shows exactly the numbers of
// ReportJson (jobs/report/campaign_report.h), in this order: the answer in three lines, samples
// and failures, measured parts beside their class (where the campaign draws from measured
// populations), the distribution of the spec'd output (histogram, CDF, quantiles,
// capability, yield), convergence and the samples a stated precision needs, sensitivities
// (contributors, by source, by the harmonic orders that carry the variance against the
// roller count), the orbits of the worst and the median sample (centre path with its
// enclosing circle and static equilibrium, beside the sensor signal over the revolution),
// where the file has the life columns the ISO 230-7 polar plot of the sample with the
// largest total error motion, every other output, and how each number was made. The
// answer also says, where it can, how much of the life's D_trajectory and runout one
// revolution misses.
#pragma once

#include <string>

#include "jobs/report/campaign_report.h"

namespace ringtol::jobs {

std::string ReportHtml(const CampaignReport& report);

}  // namespace ringtol::jobs
