#include "photometry_writer.hpp"

#include <cmath>
#include <ctime>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "io/atomic_file.hpp"

namespace fird {

namespace {

// The file is composed in memory and written whole (a temporary name, then a rename).
std::ostringstream open(const std::string&) {
    return std::ostringstream(std::ios::binary);
}

void finish(const std::ostringstream& out, const std::string& path) {
    write_text_file(path, out.str());
}

// Writes values ten per line (LM-63 limits lines to 256 characters).
void write_values(std::ostringstream& out, const std::vector<double>& values, const char* eol) {
    for (std::size_t i = 0; i < values.size(); ++i)
        out << fmt::format("{:.7g}", values[i])
            << ((i % 10 == 9 || i + 1 == values.size()) ? eol : " ");
}

// One line of header text: no line breaks inside.
std::string one_line(std::string s) {
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    return s;
}

std::string issue_date(const PhotometryLabels& labels) {
    if (!labels.issue_date.empty()) return labels.issue_date;
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    char text[16];
    std::strftime(text, sizeof text, "%Y-%m-%d", &utc);
    return text;
}

double downward_fraction(const CandelaTable& t) {
    CandelaTable lower = t;
    for (std::size_t c = 0; c < t.c_deg.size(); ++c)
        for (std::size_t g = 0; g < t.gamma_deg.size(); ++g)
            if (t.gamma_deg[g] > 90.0) lower.cd[c * t.gamma_deg.size() + g] = 0.0;
    const double total = integrated_flux_lm(t);
    return total > 0.0 ? integrated_flux_lm(lower) / total : 0.0;
}

} // namespace

void write_ies(const std::string& path, const CandelaTable& t, const PhotometryLabels& labels) {
    auto out = open(path);
    const char* eol = "\r\n"; // LM-63's line end
    out << "IES:LM-63-2019" << eol;
    out << "[TEST] " << one_line(labels.test) << eol;
    out << "[TESTLAB] FIRD" << eol;
    out << "[ISSUEDATE] " << issue_date(labels) << eol;
    out << "[MANUFAC] FIRD" << eol;
    out << "[LUMCAT] " << one_line(labels.luminaire) << eol;
    out << "[LUMINAIRE] " << one_line(labels.luminaire) << eol;
    if (labels.lamp_flux_lm > 0.0)
        out << fmt::format("[LAMP] light source of {:.7g} lm", labels.lamp_flux_lm) << eol;
    if (labels.simulated)
        out << "[FILEGENINFO] ray traced by FIRD; absolute candela for the source's flux" << eol;
    if (!labels.other.empty()) out << "[OTHER] " << one_line(labels.other) << eol;
    out << "TILT=NONE" << eol;
    // The full C range, closed at 360 (a copy of C0) as LM-63 writes 0-360 tables.
    std::vector<double> h = t.c_deg;
    const bool rotational = h.size() == 1;
    if (!rotational) h.push_back(360.0);
    out << fmt::format("1 -1 1 {} {} 1 2 0 0 0", t.gamma_deg.size(), h.size()) << eol;
    // Ballast factor, file generation type (1.XYZAB: Y = 1, simulated), input watts.
    out << (labels.simulated ? "1 1.00010 0" : "1 1.00001 0") << eol;
    write_values(out, t.gamma_deg, eol);
    write_values(out, h, eol);
    for (std::size_t c = 0; c < h.size(); ++c) {
        const std::size_t plane = c % t.c_deg.size();
        std::vector<double> v(t.cd.begin() + std::ptrdiff_t(plane * t.gamma_deg.size()),
                              t.cd.begin() + std::ptrdiff_t((plane + 1) * t.gamma_deg.size()));
        write_values(out, v, eol);
    }
    finish(out, path);
}

void write_ldt(const std::string& path, const CandelaTable& t, const PhotometryLabels& labels) {
    auto out = open(path);
    const char* eol = "\r\n";
    const double flux = integrated_flux_lm(t);
    if (!(flux > 0.0))
        throw std::runtime_error(fmt::format("{}: the distribution has no flux to write", path));
    const std::size_t mc = t.c_deg.size(), ng = t.gamma_deg.size();
    const bool rotational = mc == 1;
    double dc = 0.0;
    if (mc > 1) {
        dc = t.c_deg[1] - t.c_deg[0];
        for (std::size_t k = 2; k < mc; ++k)
            if (std::abs(t.c_deg[k] - t.c_deg[k - 1] - dc) > 1e-9) dc = 0.0; // not equidistant
    }
    double dg = ng > 1 ? t.gamma_deg[1] - t.gamma_deg[0] : 0.0;
    for (std::size_t g = 2; g < ng; ++g)
        if (std::abs(t.gamma_deg[g] - t.gamma_deg[g - 1] - dg) > 1e-9) dg = 0.0;
    const auto line = [&](const std::string& s) { out << one_line(s) << eol; };
    line("FIRD");
    line(rotational ? "1" : "0");    // Ityp: point source, rotationally symmetric or not
    line(rotational ? "1" : "0");    // Isym
    line(fmt::format("{}", mc));     // Mc
    line(fmt::format("{:.7g}", dc)); // Dc
    line(fmt::format("{}", ng));     // Ng
    line(fmt::format("{:.7g}", dg)); // Dg
    line(labels.test);               // measurement report
    line(labels.luminaire);          // luminaire name
    line("FIRD");                    // luminaire number
    line(path.substr(path.find_last_of('/') + 1));                  // file name
    line(labels.other.empty() ? issue_date(labels) : labels.other); // date / user
    for (int k = 0; k < 9; ++k) // luminaire and luminous-area dimensions (mm)
        line("0");
    line(fmt::format("{:.4f}", 100.0 * downward_fraction(t))); // DFF %
    // The lamp is the light source; the luminaire emits the table's flux of it.
    const double lamp_flux = labels.lamp_flux_lm > 0.0 ? labels.lamp_flux_lm : flux;
    line(fmt::format("{:.7g}", 100.0 * flux / lamp_flux)); // LORL %
    line("1");                              // conversion factor for luminous intensities
    line("0");                              // tilt during measurement
    line("1");                              // lamp sets
    line("1");                              // lamps
    line("FIRD far field");                 // lamp type
    line(fmt::format("{:.7g}", lamp_flux)); // total lamp flux (lm)
    line("0");                              // colour temperature
    line("0");                              // colour rendering
    line("0");                              // wattage
    for (int k = 0; k < 10; ++k)            // direct ratios (utilization): not computed
        line("0");
    for (double c : t.c_deg)
        line(fmt::format("{:.7g}", c));
    for (double g : t.gamma_deg)
        line(fmt::format("{:.7g}", g));
    for (double v : t.cd)
        line(fmt::format("{:.7g}", v * 1000.0 / lamp_flux));
    finish(out, path);
}

} // namespace fird
