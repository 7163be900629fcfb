// Reads of the API through the types openapi-typescript generates from
// openapi.yaml, checked with `tsc --strict --noEmit`: typed result fields
// compile, typos do not (each @ts-expect-error must meet an error).
import type { components, paths } from "./api";

type S = components["schemas"];

export function summary(view: S["JobView"]): string {
  const r = view.result;
  if (!r) return view.status;
  switch (r.kind) {
    case "time_history": {
      const overturned: boolean = r.overturned;
      const mode: number | null | undefined = r.mode;
      const demand: number | null | undefined = r.peak_friction_demand;
      const first = r.impacts?.[0]?.t;
      return `${overturned} ${mode} ${demand} ${first} ${r.engine.version}`;
    }
    case "spectrum": {
      const t = r.spectrum[0].transitions[0];
      const a: number = t.a_alpha_g;
      const up: "up" | "down" = t.direction;
      return `${a} ${up} ${r.spectrum[0].min_overturn_alpha_g}`;
    }
    case "friction_spectrum": {
      const p = r.points[0];
      const lifted: boolean | undefined = p.lift_off;
      return `${p.peak_friction_demand ?? "unbounded"} ${lifted}`;
    }
    case "forensic": {
      if (r.excitation === "ground_motion") {
        const lowest: number | undefined = r.consistent_scale?.[0]?.[0];
        const pga: number | undefined = r.record?.pga_g;
        const first = r.per_observation?.[0];
        const threshold: number | undefined = first?.threshold_scale;
        return `${lowest} ${pga} ${threshold} ${r.bounds.min_scale}`;
      }
      const type: string | undefined = r.pulse?.type;
      return `${type} ${r.frequencies.length}`;
    }
    case "record_spectrum": {
      const size = r.spectrum[0];
      const r_m: number = size.R_m;
      const min: number | null = size.min_overturn_scale;
      const pga: number = r.record.pga_g;
      return `${r_m} ${min} ${pga} ${size.transitions[0]?.scale}`;
    }
    case "fragility": {
      const stripe = r.stripes[0];
      // null only under a vertical motion, for a stripe whose every sample lifted off.
      const p: number | null = stripe.p;
      const lo: number | null = stripe.interval_95[0];
      const median: number | undefined = r.lognormal?.median;
      return `${p} ${lo} ${median} ${r.monotone}`;
    }
    case "survival": {
      const rate: number = r.rocks[0].annual_toppling_rate;
      const ps: number | undefined = r.ages?.[0]?.survival_probability;
      const s: number | null | undefined = r.ages?.[0]?.rate_scale_at_5_percent;
      const joint: number | undefined = r.joint?.survival_probability;
      return `${rate} ${ps} ${s} ${joint}`;
    }
  }
}

export const spec: S["TimeHistorySpec"] = {
  kind: "time_history",
  block: { alpha: 0.25, p: 2.14, eta: 0.9 },
  pulse: { type: "one_sine", omega_ratio: 5, a_p_alpha_g: 4 },
  formulation: "nonlinear",
};

export const typoFormulation: S["TimeHistorySpec"] = {
  kind: "time_history",
  block: { alpha: 0.25, p: 2.14 },
  pulse: { type: "one_sine", omega_ratio: 5, a_p_alpha_g: 4 },
  // @ts-expect-error a misspelt formulation is refused
  formulation: "nonlinaer",
};

export const typoPulse: S["TimeHistorySpec"] = {
  kind: "time_history",
  block: { alpha: 0.25, p: 2.14 },
  // @ts-expect-error a misspelt pulse type is refused
  pulse: { type: "one_sin", omega_ratio: 5, a_p_alpha_g: 4 },
};

export const onRecord: S["ForensicSpec"] = {
  kind: "forensic",
  ground_motion: { dt: 0.01, unit: "g", acc: [0, 0.3, -0.2, 0] },
  observations: [{ name: "cabinet", b: 0.3, h: 0.9, overturned: false }],
  pga_g: { from: 0.05, to: 2 },
};

export function wrongExcitation(r: S["ForensicResult"]): void {
  // @ts-expect-error excitation is "pulse" or "ground_motion"
  const e: "record" = r.excitation;
  void e;
}

export function wrongKind(r: S["TimeHistoryResult"]): void {
  // @ts-expect-error the kind of a time-history result is "time_history"
  const k: "spectrum" = r.kind;
  // @ts-expect-error overturned is a boolean
  const o: string = r.overturned;
  void k;
  void o;
}

export type Csv = paths["/v1/jobs/{id}/result"]["get"]["responses"][200]["content"]["text/csv"];
export type Svg = paths["/v1/jobs/{id}/plot.svg"]["get"]["responses"][200]["content"]["image/svg+xml"];
export const csv: Csv = "t_s,theta_rad\n";
export const svg: Svg = "<svg/>";

export function record(view: S["RecordView"]): string {
  const samples: number = view.samples;
  const pga: number = view.pga_g;
  const kinds: string[] = view.warnings.map((w) => w.kind);
  return `${view.id} ${view.format} ${samples} ${view.dt} ${pga} ${kinds} ${view.links.csv}`;
}

export function wrongRecord(view: S["RecordView"]): void {
  // @ts-expect-error samples is a number
  const n: string = view.samples;
  // @ts-expect-error a record has no `acc` in its metadata
  const acc: number[] = view.acc;
  void n;
  void acc;
}

export const onStoredRecord: S["TimeHistorySpec"] = {
  kind: "time_history",
  block: { alpha: 0.15, p: 2 },
  ground_motion: { record: "0dc0d39595ca573e58ba7a9d57de74b0" },
};

export type RecordFile = paths["/v1/records"]["post"]["requestBody"]["content"]["text/plain"];
export const recordFile: RecordFile = "time_s,acc_g\n0.00,0.0\n0.01,0.1\n";
export type Uploaded = paths["/v1/records"]["post"]["responses"][201]["content"]["application/json"];
export const uploadedSamples = (u: Uploaded): number => u.samples;
