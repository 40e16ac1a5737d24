"""One self-contained HTML page: headings, tables, text and Plotly figures, with plotly.js inlined.

Figures are built with plotly.py (graph_objects) and drawn in the browser by the plotly.js bundle
the job names (scripts/setup.sh installs the minified "basic" bundle from npm). Each figure's JSON
sits in its own <script type="application/json"> element; a short script at the end of the page
draws them all and, when every one is drawn, sets document.body.dataset.plotsRendered to their
count (the browser test waits for it). The plotly_white template is written once for all figures.
Nothing refers to anything outside the file.
"""

import html
import json
import os

import plotly.io as pio
import plotly.utils

from .errors import ReportInputError

_CSS = """
body{font-family:-apple-system,"Segoe UI",Helvetica,Arial,sans-serif;margin:0;color:#222}
header{background:#2a3f5f;color:#fff;padding:14px 24px}
header h1{margin:0;font-size:1.4em}
header p{margin:4px 0 0 0;opacity:.85}
nav{padding:6px 24px;background:#eef1f6;position:sticky;top:0;z-index:10;font-size:.9em}
nav a{margin-right:14px;color:#2a3f5f}
main{padding:8px 24px 40px 24px;max-width:1500px}
h2{border-bottom:1px solid #ccd;padding-bottom:3px;margin-top:28px}
h3{margin-bottom:4px}
table{border-collapse:collapse;font-size:.88em;margin:6px 0}
td,th{border:1px solid #ccd;padding:2px 8px;text-align:right;vertical-align:top}
th{background:#f3f5f9}
td.text{white-space:nowrap}
td.text,th.text{text-align:left}
tr.worse td{background:#fde0e0}
tr.better td{background:#dff5e0}
tr.failed td{background:#fdeede}
p.note{color:#7a5400;background:#fff7e0;border-left:3px solid #e0b040;padding:4px 10px}
pre{background:#f6f8fa;padding:8px;overflow:auto;max-height:480px;font-size:.82em}
details{margin:6px 0}
summary{cursor:pointer;color:#2a3f5f}
.figure{margin:6px 0 18px 0}
.caption{font-size:.88em;color:#444;margin:2px 0 0 0;max-width:1100px}
"""

# Draws every figure of the page; sets body.dataset.plotsRendered when all are drawn (or
# plotsFailed with the error). A point whose customdata names an .html file opens it on click.
_RENDER_JS = """
(function () {
  var template = JSON.parse(document.getElementById('sb-template').textContent);
  var specs = document.querySelectorAll('script.sb-figure');
  var drawn = [];
  specs.forEach(function (s) {
    var spec = JSON.parse(s.textContent);
    spec.layout.template = template;
    var div = document.getElementById(s.getAttribute('data-target'));
    var config = Object.assign({displaylogo: false, responsive: true}, spec.config || {});
    drawn.push(Plotly.newPlot(div, spec.data, spec.layout, config).then(function (gd) {
      gd.on('plotly_click', function (event) {
        var p = event.points && event.points[0];
        var link = p && p.customdata;
        if (Array.isArray(link)) link = link[link.length - 1];
        if (typeof link === 'string' && /\\.html$/.test(link)) window.open(link, '_blank');
      });
      return gd;
    }));
  });
  Promise.all(drawn).then(function () {
    document.body.dataset.plotsRendered = String(drawn.length);
  }, function (e) {
    document.body.dataset.plotsFailed = String(e);
    console.error('plot failed: ' + e);
  });
})();
"""


def _json_for_script(value):
    """Compact JSON safe inside a <script> element: <, > and & escaped (no '</script>' can end
    it); NaN and infinities, which JSON lacks, as null (Plotly: a gap)."""
    try:
        text = json.dumps(value, separators=(",", ":"), allow_nan=False,
                          default=plotly.utils.PlotlyJSONEncoder().default)
    except ValueError:  # a NaN somewhere: Plotly's encoder turns it into null
        plain = json.loads(json.dumps(value, cls=plotly.utils.PlotlyJSONEncoder))
        text = json.dumps(plain, separators=(",", ":"))
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def escape(text):
    return html.escape(str(text), quote=True)


class Page:
    def __init__(self, title, subtitle=""):
        self._title = title
        self._subtitle = subtitle
        self._parts = []
        self._nav = []
        self._figures = 0

    def section(self, title, anchor):
        self._nav.append((anchor, title))
        self._parts.append(f'<h2 id="{escape(anchor)}">{escape(title)}</h2>')

    def subsection(self, title):
        self._parts.append(f"<h3>{escape(title)}</h3>")

    def paragraph(self, text):
        self._parts.append(f"<p>{escape(text)}</p>")

    def raw(self, markup):
        self._parts.append(markup)

    def note(self, text, at=None):
        """A visible remark: data the report could not draw, and why. `at`: a mark() to put it
        at instead of the end."""
        markup = f'<p class="note">{escape(text)}</p>'
        if at is None:
            self._parts.append(markup)
        else:
            self._parts.insert(at, markup)

    def mark(self):
        """The current end of the page, for a later note(at=...)."""
        return len(self._parts)

    def table(self, header, rows, text_columns=1, row_classes=None, markup_columns=()):
        """A table; the first `text_columns` columns are left-aligned text, the rest numbers.
        Cells are escaped, except those of the columns in `markup_columns` (links)."""
        out = ["<table><tr>"]
        for i, h in enumerate(header):
            cls = ' class="text"' if i < text_columns else ""
            out.append(f"<th{cls}>{escape(h)}</th>")
        out.append("</tr>")
        for r, row in enumerate(rows):
            cls = f' class="{escape(row_classes[r])}"' if row_classes and row_classes[r] else ""
            out.append(f"<tr{cls}>")
            for i, cell in enumerate(row):
                align = ' class="text"' if i < text_columns else ""
                content = cell if i in markup_columns else escape(cell)
                out.append(f"<td{align}>{content}</td>")
            out.append("</tr>")
        out.append("</table>")
        self._parts.append("".join(out))

    def preformatted(self, summary, text, open_=False):
        """Text in a collapsible block (scenario files, options, error messages)."""
        state = " open" if open_ else ""
        self._parts.append(f"<details{state}><summary>{escape(summary)}</summary>"
                           f"<pre>{escape(text)}</pre></details>")

    def figure(self, fig, caption="", config=None):
        """A plotly.py figure, drawn by the page's script; config: plotly.js options."""
        self._figures += 1
        div = f"fig{self._figures}"
        spec = fig.to_plotly_json()
        spec["layout"].pop("template", None)
        spec = {"data": spec["data"], "layout": spec["layout"], "config": config or {}}
        caption_html = f'<p class="caption">{escape(caption)}</p>' if caption else ""
        self._parts.append(
            f'<div class="figure"><div id="{div}" class="sb-plot"></div>{caption_html}'
            f'<script type="application/json" class="sb-figure" data-target="{div}">'
            f"{_json_for_script(spec)}</script></div>")

    @property
    def figure_count(self):
        return self._figures

    def write(self, out_path, plotly_js_path):
        try:
            with open(plotly_js_path, encoding="utf-8") as f:
                plotly_js = f.read()
        except OSError as e:
            raise ReportInputError(f"{plotly_js_path}: cannot read plotly.js: {e.strerror}") from None
        # A script element ends at the first '</script'; the bundle has none, but make sure.
        plotly_js = plotly_js.replace("</script", "<\\/script")
        template = pio.templates["plotly_white"].to_plotly_json()
        nav = "".join(f'<a href="#{escape(a)}">{escape(t)}</a>' for a, t in self._nav)
        subtitle = f"<p>{escape(self._subtitle)}</p>" if self._subtitle else ""
        page = (
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{escape(self._title)}</title><style>{_CSS}</style>\n"
            f"<script>{plotly_js}</script>\n</head><body>\n"
            f"<header><h1>{escape(self._title)}</h1>{subtitle}</header>\n"
            f"<nav>{nav}</nav>\n<main>\n" + "\n".join(self._parts) + "\n</main>\n"
            f'<script type="application/json" id="sb-template">{_json_for_script(template)}</script>\n'
            f"<script>{_RENDER_JS}</script>\n</body></html>\n")
        directory = os.path.dirname(os.path.abspath(out_path))
        try:
            os.makedirs(directory, exist_ok=True)
            temporary = out_path + ".partial"
            with open(temporary, "w", encoding="utf-8") as f:
                f.write(page)
            os.replace(temporary, out_path)
        except OSError as e:
            raise ReportInputError(f"{out_path}: cannot write: {e.strerror}") from None
