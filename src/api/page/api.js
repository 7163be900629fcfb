// @ts-check
// The service's HTTP API as the page uses it: the token, problem+json
// errors, and Server-Sent Events read with fetch (so that a token can be sent).

import { $input } from "./dom.js";

/** @typedef {import('topple-api').components['schemas']['Problem']} Problem */

/**
 * A problem as the page shows it: the service's problem+json (or one of the
 * page's own), with what the page adds.
 * @typedef {Partial<Omit<Problem, "title">> & {
 *   title: string,
 *   file?: string,
 *   notice?: boolean,
 *   retry_after?: number | string,
 *   parameter?: string | null,
 *   header?: string | null,
 *   limit?: string | null,
 *   maximum?: unknown,
 *   value?: unknown,
 * }} PageProblem
 */

/**
 * The request headers: `extra`, and the token when one is filled in.
 * @param {Record<string, string>} [extra]
 * @returns {Record<string, string>}
 */
export function headers(extra) {
  const h = Object.assign({}, extra || {});
  const token = $input("f-token").value.trim();
  if (token) h["Authorization"] = "Bearer " + token;
  return h;
}

/**
 * A failed response as {status, title, detail, pointer, ...}.
 * @param {Response} resp
 * @returns {Promise<PageProblem>}
 */
export async function problemOf(resp) {
  /** @type {any} */
  let body = null;
  try { body = await resp.json(); } catch (_) { /* not JSON */ }
  if (!body || typeof body !== "object") body = {};
  body.status = body.status || resp.status;
  body.title = body.title || resp.statusText || "Error";
  if (!body.retry_after && resp.headers.get("retry-after")) body.retry_after = resp.headers.get("retry-after");
  return body;
}

/**
 * Reads a stream of Server-Sent Events to its end: `onEvent(name, data)`
 * for each event that carries data.
 * @param {ReadableStream<Uint8Array>} body
 * @param {(name: string, data: string) => void} onEvent
 */
export async function eachEvent(body, onEvent) {
  const reader = body.getReader();
  const decoder = new TextDecoder();
  let buffer = "";
  for (;;) {
    const { value, done } = await reader.read();
    if (done) break;
    buffer += decoder.decode(value, { stream: true });
    let cut;
    while ((cut = buffer.indexOf("\n\n")) >= 0) {
      const block = buffer.slice(0, cut);
      buffer = buffer.slice(cut + 2);
      let name = "message", data = "";
      for (const line of block.split("\n")) {
        if (line.startsWith("event: ")) name = line.slice(7);
        else if (line.startsWith("data: ")) data += line.slice(6);
      }
      if (!data) continue;
      onEvent(name, data);
    }
  }
}
