// @ts-check
// A record's motion, drawn: ü_g/g against t, in SVG.

import { fmt } from "./format.js";

const SVG_NS = "http://www.w3.org/2000/svg";
/**
 * An SVG element with attributes and text.
 * @param {string} tag
 * @param {Record<string, string | number>} [attrs]
 * @param {string} [text]
 */
function svgEl(tag, attrs, text) {
  const el = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs || {})) el.setAttribute(k, String(v));
  if (text !== undefined) el.textContent = text;
  return el;
}

// Round tick values (1, 2 or 5 × 10^k apart) inside [lo, hi], about n of them.
/**
 * @param {number} lo
 * @param {number} hi
 * @param {number} n
 */
function niceTicks(lo, hi, n) {
  const raw = (hi - lo) / n;
  const mag = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = /** @type {number} */ ([1, 2, 5, 10].find((f) => f * mag >= raw)) * mag;
  const out = [];
  for (let v = Math.ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step) out.push(Number(v.toPrecision(12)));
  return out;
}
/** @param {number} v */
const tickText = (v) => String(Number(v.toPrecision(4))).replace("-", "−");

// ü_g/g against t: the samples (at most two a pixel column: the lowest and
// highest of each), the peak marked.
/**
 * @param {number} dt
 * @param {number[]} acc
 * @param {string} name
 */
export function motionSvg(dt, acc, name) {
  const W = 320, H = 150, L = 40, R = 6, T = 16, B = 31;
  const n = acc.length;
  const tEnd = Math.max((n - 1) * dt, dt);
  let peak = 0, at = 0;
  for (let i = 0; i < n; i++) {
    const v = Math.abs(acc[i]);
    if (v > peak) { peak = v; at = i; }
  }
  const yLim = peak > 0 ? peak * 1.1 : 1;
  /** @param {number} t */
  const px = (t) => L + (t / tEnd) * (W - L - R);
  /** @param {number} v */
  const py = (v) => T + ((yLim - v) / (2 * yLim)) * (H - T - B);
  /** @param {number} x */
  const r2 = (x) => Math.round(x * 100) / 100;
  const svg = svgEl("svg", {
    viewBox: `0 0 ${W} ${H}`, role: "img", "data-peak-g": peak, "data-samples": n,
    "aria-label": `Ground acceleration of ${name}: ${n} samples over ${fmt(tEnd)} s, peak ${fmt(peak)} g at ${fmt(at * dt)} s`
  });
  for (const v of niceTicks(-yLim, yLim, 4)) {
    svg.append(svgEl("line", { class: v === 0 ? "zero" : "grid", x1: L, x2: W - R, y1: r2(py(v)), y2: r2(py(v)) }));
    svg.append(svgEl("text", { x: L - 4, y: r2(py(v) + 3.5), "text-anchor": "end" }, tickText(v)));
  }
  for (const t of niceTicks(0, tEnd, 6)) {
    svg.append(svgEl("line", { class: "axis", x1: r2(px(t)), x2: r2(px(t)), y1: H - B, y2: H - B + 4 }));
    svg.append(svgEl("text", { x: r2(px(t)), y: H - B + 14, "text-anchor": "middle" }, tickText(t)));
  }
  svg.append(svgEl("rect", { class: "axis", x: L, y: T, width: W - L - R, height: H - T - B }));
  const points = [];
  const columns = 2 * (W - L - R);
  if (n <= 2 * columns) {
    for (let i = 0; i < n; i++) points.push(`${r2(px(i * dt))},${r2(py(acc[i]))}`);
  } else {
    for (let c = 0; c < columns; c++) {
      const from = Math.floor((c * n) / columns), to = Math.floor(((c + 1) * n) / columns);
      let lo = from, hi = from;
      for (let i = from; i < to; i++) {
        if (acc[i] < acc[lo]) lo = i;
        if (acc[i] > acc[hi]) hi = i;
      }
      for (const i of lo <= hi ? [lo, hi] : [hi, lo]) points.push(`${r2(px(i * dt))},${r2(py(acc[i]))}`);
    }
  }
  svg.append(svgEl("polyline", { class: "trace", points: points.join(" ") }));
  svg.append(svgEl("circle", { class: "peak", cx: r2(px(at * dt)), cy: r2(py(acc[at])), r: 2.8 }));
  svg.append(svgEl("text", { class: "title", x: W - R, y: 11, "text-anchor": "end" }, `PGA ${fmt(peak, 3)} g at t = ${fmt(at * dt, 3)} s`));
  svg.append(svgEl("text", { x: (L + W - R) / 2, y: H - 3, "text-anchor": "middle" }, "t (s)"));
  svg.append(svgEl("text", { x: 11, y: (T + H - B) / 2, "text-anchor": "middle", transform: `rotate(-90 11 ${(T + H - B) / 2})` }, "ü_g/g"));
  return svg;
}

