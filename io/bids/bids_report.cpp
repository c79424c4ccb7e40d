// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/bids/bids_report.h"

#include "io/bids/bids.h"
#include "io/formats/json.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

namespace dtf::io {

const std::vector<std::string>& groupMetricColumns() {
  static const std::vector<std::string> cols = {
      "fa_wm_mean",   "fa_wm_median", "md_wm_mean",        "md_wm_median",     "wm_voxels",
      "brain_voxels", "wm_fraction",  "check_score_given", "check_score_best", "check_margin"};
  return cols;
}

const std::vector<std::string>& outlierMetrics() {
  static const std::vector<std::string> cols = {"fa_wm_mean", "md_wm_mean", "wm_fraction", "brain_voxels"};
  return cols;
}

namespace {

// Differences below this fraction of the median are never outliers: in a cohort of near-identical runs the
// MAD is tiny and would flag differences of no consequence.
constexpr double kMinRelativeDeviation = 0.05;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string number(double v, int precision = 5) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  if (std::abs(v) >= 1000 && std::abs(v) < 1e15 && v == std::round(v))
    std::snprintf(buf, sizeof buf, "%.0f", v);
  else
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
  return buf;
}

std::string joined(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i)
    s += (i ? sep : "") + v[i];
  return s;
}

std::string tsvField(const std::string& s) {
  if (s.empty()) return "n/a";
  std::string o;
  for (char c : s)
    o += c == '\t' || c == '\n' || c == '\r' ? ' ' : c;
  return o;
}

std::vector<std::string> flagsOf(const GroupRow& r) {
  std::vector<std::string> f;
  if (!r.ok) f.push_back("failed");
  if (r.verdict == "corrected") f.push_back("corrected");
  if (r.verdict == "inconclusive") f.push_back("inconclusive");
  if (!r.outliers.empty()) f.push_back("outlier");
  return f;
}

} // namespace

void flagOutliers(std::vector<GroupRow>& rows) {
  const auto& cols = groupMetricColumns();
  for (const std::string& name : outlierMetrics()) {
    const auto col = static_cast<std::size_t>(std::find(cols.begin(), cols.end(), name) - cols.begin());
    std::vector<double> values;
    for (const auto& r : rows)
      if (r.ok && col < r.metrics.size() && std::isfinite(r.metrics[col])) values.push_back(r.metrics[col]);
    if (values.size() < 5) continue;
    const double m = median(values);
    std::vector<double> dev;
    double meanDev = 0;
    for (double v : values) {
      dev.push_back(std::abs(v - m));
      meanDev += std::abs(v - m);
    }
    meanDev /= static_cast<double>(values.size());
    const double mad = median(dev);
    // Modified z-score: 0.6745 (x - m) / MAD; fallback (x - m) / (1.253314 MeanAD) when MAD = 0.
    const double scale = mad > 0 ? mad / 0.6745 : 1.253314 * meanDev;
    if (!(scale > 0)) continue;
    for (auto& r : rows)
      if (r.ok && col < r.metrics.size() && std::isfinite(r.metrics[col]) &&
          std::abs(r.metrics[col] - m) / scale > 3.5 &&
          std::abs(r.metrics[col] - m) > kMinRelativeDeviation * std::abs(m))
        r.outliers.push_back(name);
  }
}

std::string groupTsv(const std::vector<GroupRow>& rows) {
  std::string t = "participant_id\tsession_id\trun\tstatus\tcheck_verdict\tcheck_correction";
  for (const auto& c : groupMetricColumns())
    t += "\t" + c;
  t += "\toutliers\tmessage\n";
  for (const auto& r : rows) {
    t += tsvField(r.participant) + "\t" + tsvField(r.session) + "\t" + tsvField(r.run) + "\t" +
         (r.ok ? "ok" : "failed") + "\t" + tsvField(r.verdict) + "\t" + tsvField(r.correction);
    for (std::size_t c = 0; c < groupMetricColumns().size(); ++c)
      t += "\t" + number(c < r.metrics.size() ? r.metrics[c] : std::nan(""), 6);
    t += "\t" + tsvField(joined(r.outliers, ",")) + "\t" + tsvField(r.message) + "\n";
  }
  return t;
}

std::string htmlEscape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
    case '&':
      o += "&amp;";
      break;
    case '<':
      o += "&lt;";
      break;
    case '>':
      o += "&gt;";
      break;
    case '"':
      o += "&quot;";
      break;
    case '\'':
      o += "&#39;";
      break;
    default:
      o += c;
    }
  }
  return o;
}

namespace {

const char* kStyle = R"(
body{font-family:system-ui,sans-serif;margin:16px;background:#fafafa;color:#222}
h1{font-size:20px;margin:0 0 4px}h2{font-size:16px;margin:20px 0 6px}
.meta{color:#666;font-size:12px}
.summary span{display:inline-block;margin-right:14px}
table{border-collapse:collapse;font-size:12px;background:#fff}
th,td{border:1px solid #ddd;padding:3px 6px;text-align:left;white-space:nowrap}
th{background:#eee;cursor:pointer;user-select:none;position:sticky;top:0}
th.sorted-asc::after{content:" \25B2"}th.sorted-desc::after{content:" \25BC"}
td.num{text-align:right;font-variant-numeric:tabular-nums}
td.out{background:#f3e3ff}
td.msg{white-space:normal;max-width:480px}
.flag{display:inline-block;border-radius:3px;padding:0 5px;margin-right:3px;font-size:11px;color:#fff}
.flag-failed{background:#c62828}.flag-corrected{background:#ef6c00}.flag-inconclusive{background:#9e9d24}
.flag-outlier{background:#6a1b9a}
tr.failed td{background:#fdecea}
.mosaic{display:flex;flex-wrap:wrap;gap:8px}
.card{background:#fff;border:2px solid #ccc;padding:4px;cursor:pointer;width:max-content}
.card.failed{border-color:#c62828}.card.corrected{border-color:#ef6c00}.card.inconclusive{border-color:#9e9d24}
.card .name{font-size:11px;margin-bottom:2px}
.card img{width:96px;height:96px;object-fit:contain;background:#000;margin-right:2px}
.card .none{width:200px;height:96px;font-size:11px;color:#c62828;white-space:normal;overflow:hidden}
#detail{display:none;position:fixed;inset:0;background:rgba(0,0,0,.85);overflow:auto;padding:20px;color:#eee}
#detail.open{display:block}
#detail img{max-width:45vw;margin:4px;background:#000;vertical-align:top}
#detail figure{display:inline-block;margin:4px}
#detail figcaption{font-size:12px}
#detail .close{float:right;font-size:24px;cursor:pointer}
#detail td,#detail th{color:#222}
)";

// Sorting, the detail overlay and the self-check. Plain ES2017, no library: the page must work offline.
const char* kScript = R"(
(function(){
'use strict';
const caught=[];
window.addEventListener('error',function(e){caught.push(String(e.message||e.type));});
const origError=console.error;console.error=function(){caught.push(Array.from(arguments).join(' '));origError.apply(console,arguments);};
function cellValue(td){const v=td.getAttribute('data-v');if(v===null)return td.textContent;return v;}
function sortTable(table,col,th){
  const tbody=table.tBodies[0];const rows=Array.from(tbody.rows);
  const asc=!th.classList.contains('sorted-asc');
  table.querySelectorAll('th').forEach(function(h){h.classList.remove('sorted-asc','sorted-desc');});
  th.classList.add(asc?'sorted-asc':'sorted-desc');
  const keyed=rows.map(function(r){const s=cellValue(r.cells[col]);const n=parseFloat(s);
    return {r:r,n:(s!==''&&s!=='n/a'&&isFinite(n))?n:null,s:s};});
  keyed.sort(function(a,b){let c;
    if(a.n!==null&&b.n!==null)c=a.n-b.n;else if(a.n!==null)c=-1;else if(b.n!==null)c=1;else c=a.s.localeCompare(b.s);
    return asc?c:-c;});
  const frag=document.createDocumentFragment();keyed.forEach(function(k){frag.appendChild(k.r);});tbody.appendChild(frag);
}
document.querySelectorAll('table.sortable').forEach(function(table){
  Array.from(table.tHead.rows[0].cells).forEach(function(th,i){th.addEventListener('click',function(){sortTable(table,i,th);});});
});
const runs=JSON.parse(document.getElementById('dtf-data').textContent);
const detail=document.getElementById('detail');
function esc(s){return String(s).replace(/[&<>"']/g,function(c){return {'&':'&amp;','<':'&lt;','>':'&gt;','"':'&quot;',"'":'&#39;'}[c];});}
function openDetail(i){
  const r=runs[i];let h='<span class="close" title="close">&times;</span><h2>'+esc(r.run)+'</h2><p>'+r.flags.map(function(f){return '<span class="flag flag-'+f+'">'+f+'</span>';}).join('')+' '+esc(r.message)+'</p>';
  h+='<table><tr><th>metric</th><th>value</th></tr>';
  Object.keys(r.metrics).forEach(function(k){h+='<tr><td>'+esc(k)+'</td><td class="num">'+esc(r.metrics[k])+'</td></tr>';});
  h+='</table>';
  if(r.web)h+='<p><a class="web" href="'+encodeURI(r.web)+'" target="_blank">browse every slice (web page)</a></p>';
  r.figures.forEach(function(f){h+='<figure><a href="'+encodeURI(f.path)+'" target="_blank"><img src="'+encodeURI(f.path)+'" alt="'+esc(f.label)+'"></a><figcaption>'+esc(f.label)+'</figcaption></figure>';});
  detail.innerHTML=h;detail.classList.add('open');detail.scrollTop=0;
  detail.querySelector('.close').addEventListener('click',function(){detail.classList.remove('open');});
}
document.querySelectorAll('[data-run]').forEach(function(el){el.addEventListener('click',function(ev){ev.preventDefault();openDetail(+el.getAttribute('data-run'));});});
document.addEventListener('keydown',function(e){if(e.key==='Escape')detail.classList.remove('open');});
if(location.hash==='#timing'){
  const table=document.getElementById('all');const th=table.tHead.rows[0].cells[6];
  const t0=performance.now();sortTable(table,6,th);sortTable(table,6,th);const t1=performance.now();
  openDetail(0);const t2=performance.now();
  const pre=document.createElement('pre');pre.id='dtf-timing';
  pre.textContent=JSON.stringify({rows:table.tBodies[0].rows.length,sort_ms:(t1-t0)/2,detail_ms:t2-t1,
    script_ms:t0});
  document.body.appendChild(pre);
}
if(location.hash==='#selfcheck'){
  const imgs=Array.from(document.querySelectorAll('img'));
  const waits=imgs.map(function(img){img.loading='eager';
    if(img.complete&&img.naturalWidth>0)return Promise.resolve(true);
    return new Promise(function(res){img.addEventListener('load',function(){res(true);});img.addEventListener('error',function(){res(false);});
      const s=img.src;img.src='';img.src=s;});});
  Promise.all(waits).then(function(ok){
    const flagged={};
    document.querySelectorAll('#all tbody tr').forEach(function(tr){
      tr.querySelectorAll('.flag').forEach(function(f){const k=f.textContent;(flagged[k]=flagged[k]||[]).push(tr.getAttribute('data-id'));});});
    const lists={};document.querySelectorAll('table.flaglist').forEach(function(t){lists[t.id]=Array.from(t.tBodies[0].rows).map(function(r){return r.getAttribute('data-id');});});
    const out={images:imgs.length,loaded:ok.filter(Boolean).length,
      broken:imgs.filter(function(im,i){return !ok[i];}).map(function(im){return im.getAttribute('src');}),
      errors:caught,flagged:flagged,lists:lists,rows:document.querySelectorAll('#all tbody tr').length,
      cards:document.querySelectorAll('.card').length,
      web:Array.from(document.querySelectorAll('#all a.web')).map(function(a){return a.getAttribute('href');})};
    // Click-through: click the card with the most figures, wait for the overlay's full-size images.
    let most=null;document.querySelectorAll('.card').forEach(function(c){if(!most||c.querySelectorAll('img').length>most.querySelectorAll('img').length)most=c;});
    if(most)most.click();
    const big=Array.from(detail.querySelectorAll('img'));
    return Promise.all(big.map(function(img){if(img.complete&&img.naturalWidth>0)return Promise.resolve(true);
      return new Promise(function(res){img.addEventListener('load',function(){res(true);});img.addEventListener('error',function(){res(false);});});}))
    .then(function(bigOk){
      out.detail={run:most?most.getAttribute('data-id'):'',open:detail.classList.contains('open'),figures:big.length,
        loaded:bigOk.filter(Boolean).length,links:detail.querySelectorAll('a[href$=".png"]').length};
      out.errors=caught;
      const pre=document.createElement('pre');pre.id='dtf-selfcheck';pre.textContent=JSON.stringify(out);document.body.appendChild(pre);
    });
  });
}
})();
)";

std::string rowId(const GroupRow& r) {
  return r.run;
}

std::string flagBadges(const std::vector<std::string>& flags) {
  std::string h;
  for (const auto& f : flags)
    h += "<span class=\"flag flag-" + f + "\">" + f + "</span>";
  return h;
}

} // namespace

std::string groupReportHtml(const std::vector<GroupRow>& rows, const std::string& title,
                            const std::string& generated) {
  const auto& cols = groupMetricColumns();
  std::size_t nFailed = 0, nCorrected = 0, nInconclusive = 0, nOutlier = 0;
  for (const auto& r : rows) {
    nFailed += !r.ok;
    nCorrected += r.verdict == "corrected";
    nInconclusive += r.verdict == "inconclusive";
    nOutlier += !r.outliers.empty();
  }
  std::string h;
  h.reserve(4096 + rows.size() * 3000);
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + htmlEscape(title) +
       "</title>\n<style>" + kStyle + "</style></head><body>\n";
  h += "<h1>" + htmlEscape(title) + "</h1>\n<div class=\"meta\">" + htmlEscape(generated) + "</div>\n";
  h += "<p class=\"summary\"><span>" + std::to_string(rows.size()) + " runs</span><span>" +
       std::to_string(rows.size() - nFailed) + " ok</span><span>" + flagBadges({"failed"}) +
       std::to_string(nFailed) + "</span><span>" + flagBadges({"corrected"}) + std::to_string(nCorrected) +
       "</span><span>" + flagBadges({"inconclusive"}) + std::to_string(nInconclusive) + "</span><span>" +
       flagBadges({"outlier"}) + std::to_string(nOutlier) + "</span></p>\n";
  h += "<p class=\"meta\">Outliers: among the runs that succeeded (at least 5), a metric of " +
       htmlEscape(joined(outlierMetrics(), ", ")) +
       " whose modified z-score 0.6745&middot;(x &minus; median)/MAD exceeds 3.5 in magnitude "
       "(1.2533&middot;mean "
       "absolute deviation replaces MAD/0.6745 when the MAD is 0) and that differs from the median by more "
       "than 5%. White matter: FA &ge; 0.3 inside the fit's "
       "mask; MD in 10<sup>&minus;3</sup> mm<sup>2</sup>/s. Click a run for its full figures; click a column "
       "header to sort.</p>\n";

  // Tables of the runs that need a look, one per flag.
  struct FlagList {
    const char* id;
    const char* heading;
    bool (*has)(const GroupRow&);
  };
  const FlagList lists[] = {
      {"list-failed", "Failed runs", [](const GroupRow& r) { return !r.ok; }},
      {"list-corrected", "Gradient table corrected by the orientation check",
       [](const GroupRow& r) { return r.verdict == "corrected"; }},
      {"list-inconclusive", "Orientation check inconclusive",
       [](const GroupRow& r) { return r.verdict == "inconclusive"; }},
      {"list-outlier", "Outlying metrics", [](const GroupRow& r) { return !r.outliers.empty(); }},
  };
  for (const auto& l : lists) {
    h += std::string("<h2>") + l.heading + "</h2>\n<table class=\"flaglist\" id=\"" + l.id +
         "\"><thead><tr><th>run</th><th>verdict</th><th>correction</th><th>outliers</th><th>message</th></tr>"
         "</thead><tbody>\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const GroupRow& r = rows[i];
      if (!l.has(r)) continue;
      h += "<tr data-id=\"" + htmlEscape(rowId(r)) + "\"><td><a href=\"#\" data-run=\"" + std::to_string(i) +
           "\">" + htmlEscape(r.run) + "</a></td><td>" + htmlEscape(r.verdict) + "</td><td>" +
           htmlEscape(r.correction) + "</td><td>" + htmlEscape(joined(r.outliers, ", ")) +
           "</td><td class=\"msg\">" + htmlEscape(r.message) + "</td></tr>\n";
    }
    h += "</tbody></table>\n";
  }

  h += "<h2>All runs</h2>\n<table class=\"sortable\" id=\"all\"><thead><tr><th>run</th><th>participant</th>"
       "<th>session</th><th>status</th><th>verdict</th><th>correction</th>";
  for (const auto& c : cols)
    h += "<th>" + htmlEscape(c) + "</th>";
  h += "<th>seconds</th><th>flags</th><th>message</th></tr></thead><tbody>\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const GroupRow& r = rows[i];
    h += std::string("<tr") + (r.ok ? "" : " class=\"failed\"") + " data-id=\"" + htmlEscape(rowId(r)) +
         "\"><td><a href=\"#\" data-run=\"" + std::to_string(i) + "\">" + htmlEscape(r.run) + "</a>" +
         (r.webPage.empty() ? std::string()
                            : " <a class=\"web\" href=\"" + htmlEscape(r.webPage) + "\" target=\"_blank\">web</a>") +
         "</td><td>" + htmlEscape(r.participant) + "</td><td>" +
         htmlEscape(r.session.empty() ? "n/a" : r.session) + "</td><td>" + (r.ok ? "ok" : "failed") +
         "</td><td>" + htmlEscape(r.verdict) + "</td><td>" + htmlEscape(r.correction) + "</td>";
    for (std::size_t c = 0; c < cols.size(); ++c) {
      const double v = c < r.metrics.size() ? r.metrics[c] : std::nan("");
      const bool out = std::find(r.outliers.begin(), r.outliers.end(), cols[c]) != r.outliers.end();
      h += std::string("<td class=\"num") + (out ? " out" : "") + "\" data-v=\"" + number(v, 9) + "\">" +
           number(v, 4) + "</td>";
    }
    h += "<td class=\"num\" data-v=\"" + number(r.seconds, 6) + "\">" + number(r.seconds, 3) + "</td><td>" +
         flagBadges(flagsOf(r)) + "</td><td class=\"msg\">" + htmlEscape(r.message) + "</td></tr>\n";
  }
  h += "</tbody></table>\n";

  h += "<h2>Mosaic</h2>\n<div class=\"mosaic\">\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const GroupRow& r = rows[i];
    std::string cls = "card";
    if (!r.ok)
      cls += " failed";
    else if (r.verdict != "ok")
      cls += " " + r.verdict;
    h += "<div class=\"" + cls + "\" data-run=\"" + std::to_string(i) + "\" data-id=\"" +
         htmlEscape(rowId(r)) + "\"><div class=\"name\">" + htmlEscape(r.run) + " " + flagBadges(flagsOf(r)) +
         "</div>";
    if (r.figures.empty()) h += "<div class=\"none\">" + htmlEscape(r.message) + "</div>";
    for (const auto& f : r.figures)
      h += "<img loading=\"lazy\" src=\"" + htmlEscape(f.path) + "\" alt=\"" + htmlEscape(f.label) +
           "\" title=\"" + htmlEscape(f.label) + "\">";
    h += "</div>\n";
  }
  h += "</div>\n<div id=\"detail\"></div>\n";

  // Per-run data for the detail overlay. '<' is written as \u003c (the same string in JSON) so that no
  // "</script>" or "<!--" inside a name can end or change the element.
  nlohmann::ordered_json data = nlohmann::ordered_json::array();
  for (const GroupRow& r : rows) {
    nlohmann::ordered_json metrics = nlohmann::ordered_json::object();
    for (std::size_t c = 0; c < cols.size(); ++c)
      metrics[cols[c]] = number(c < r.metrics.size() ? r.metrics[c] : std::nan(""), 6);
    nlohmann::ordered_json figures = nlohmann::ordered_json::array();
    for (const auto& f : r.figures)
      figures.push_back({{"label", f.label}, {"path", f.path}});
    nlohmann::ordered_json run = {{"run", r.run},
                                  {"message", r.message},
                                  {"flags", flagsOf(r)},
                                  {"metrics", metrics},
                                  {"figures", figures}};
    if (!r.webPage.empty()) run["web"] = r.webPage;
    data.push_back(run);
  }
  std::string safe;
  for (char c : jsonText(data))
    safe += c == '<' ? std::string("\\u003c") : std::string(1, c);
  h += "<script type=\"application/json\" id=\"dtf-data\">" + safe + "</script>\n";
  h += std::string("<script>") + kScript + "</script>\n</body></html>\n";
  return h;
}

} // namespace dtf::io
