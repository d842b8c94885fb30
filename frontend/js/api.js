// The REST API of docs/api.md, from the same origin that serves the page.

export class ApiError extends Error {
  constructor(status, detail, field) {
    super(detail);
    this.status = status;
    this.field = field; // the request field a 422 names, e.g. "study.case.entry.velocity_fps"
  }
}

function detailText(detail, fallback) {
  if (typeof detail === "string") return detail;
  if (Array.isArray(detail)) return detail.map((d) => `${(d.loc || []).join(".")}: ${d.msg}`).join("; ");
  return fallback;
}

// FOOTPRINT_API_TOKEN, asked for once when the service first answers 401 and kept for this browser session
const TOKEN_KEY = "footprint-api-token";

function request(path, { method, body, contentType, signal }) {
  const init = { method, headers: {}, signal };
  if (body !== undefined) {
    const text = typeof body === "string";
    init.body = text ? body : JSON.stringify(body);
    init.headers["Content-Type"] = contentType || (text ? "text/plain" : "application/json");
  }
  const token = sessionStorage.getItem(TOKEN_KEY);
  if (token) init.headers.Authorization = `Bearer ${token}`;
  return fetch(path, init);
}

/** fetch a JSON (or text) resource; a non-2xx answer raises ApiError with the body's one-line detail. A write the
 * service refuses without its token (401) asks for the token once, keeps it for the session and is sent again. */
export async function api(path, { method = "GET", body, contentType, signal } = {}) {
  const options = { method, body, contentType, signal };
  let res = await request(path, options);
  if (res.status === 401) {
    sessionStorage.removeItem(TOKEN_KEY);
    const given = window.prompt("This service asks for its API token to store changes (FOOTPRINT_API_TOKEN):");
    if (given && given.trim()) {
      sessionStorage.setItem(TOKEN_KEY, given.trim());
      res = await request(path, options);
    }
  }
  if (!res.ok) {
    let data = {};
    try { data = await res.json(); } catch { /* a body that is not JSON: the status text says enough */ }
    let field = data.field ?? null;
    if (!field && Array.isArray(data.detail) && data.detail[0]?.loc) field = data.detail[0].loc.slice(1).join(".");
    throw new ApiError(res.status, detailText(data.detail, `${res.status} ${res.statusText}`), field);
  }
  if (res.status === 204) return null;
  return (res.headers.get("content-type") || "").includes("json") ? res.json() : res.text();
}
