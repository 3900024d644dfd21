// Self-contained HTML pages (the validation report of `ricochet report`): text, tables and
// figures in one file that opens in a browser with no network. Figures are gnuplot SVGs or PNGs
// (report/plot.hpp) embedded as base64 data URIs, so that the element ids of different gnuplot
// SVGs cannot collide; styles are inline; nothing is loaded from elsewhere.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "report/plot.hpp"

namespace ricochet::report {

/// Escapes & < > " ' for HTML text and attribute values.
std::string html_escape(std::string_view text);
/// Standard base64 (RFC 4648, with padding).
std::string base64(std::string_view bytes);

/// The SVG without its empty groups (<g ...> with only whitespace before </g>, nested ones too),
/// which draw nothing: gnuplot's SVG terminal opens one for every pen change, drawn or not, and
/// they are about a quarter of a figure's bytes. Everything else is kept byte for byte.
std::string compact_svg(std::string_view svg);

/// An HTML page built piece by piece. All text arguments are plain text (escaped here).
class HtmlPage {
 public:
  explicit HtmlPage(std::string title);

  /// <h1>..<h4>; `id` (optional) makes it a link target of the table of contents (h2 only).
  void heading(int level, const std::string& text, const std::string& id = "");
  void paragraph(const std::string& text);
  /// The one sentence a section opens with, set apart (class "verdict").
  void verdict(const std::string& text);
  /// A paragraph with a bold lead-in, e.g. ("Verdict", "missing physics").
  void labelled(const std::string& label, const std::string& text);
  void list(const std::vector<std::string>& items);
  /// A table; cells that parse as a number are right-aligned.
  void table(const std::vector<std::string>& header,
             const std::vector<std::vector<std::string>>& rows, const std::string& caption = "");
  void preformatted(const std::string& text);
  /// Opens a collapsible block (<details>, closed until the reader clicks `summary`); everything
  /// added until end_details() goes into it. Blocks may nest.
  void begin_details(const std::string& summary);
  void end_details();
  /// Embeds an SVG or PNG file (e.g. written by render) as a figure with a caption. Throws
  /// std::runtime_error naming the file if it cannot be read or is not an SVG.
  void figure_file(const std::string& svg_path, const std::string& caption);
  /// Renders `figure` with gnuplot into a temporary file and embeds it: as SVG, or as PNG when it
  /// has more than kMaxVectorPanels panels or kMaxVectorPoints points (the page's size).
  void figure(const Figure& figure, const std::string& caption);
  static constexpr std::size_t kMaxVectorPanels = 2, kMaxVectorPoints = 1000;

  /// Number of figures embedded so far.
  std::size_t figures() const { return figures_; }
  /// The whole page.
  std::string html() const;
  /// Writes the page (parent directories created). Throws std::runtime_error on failure.
  void write(const std::string& path) const;

 private:
  std::string title_;
  std::vector<std::pair<std::string, std::string>> toc_;  // (id, text)
  std::string body_;
  std::size_t figures_ = 0;
  int open_details_ = 0;
};

}  // namespace ricochet::report
