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

/** fetch a JSON (or text) resource; a non-2xx answer raises ApiError with the body's one-line detail. */
export async function api(path, { method = "GET", body, contentType, signal } = {}) {
  const init = { method, headers: {}, signal };
  if (body !== undefined) {
    const text = typeof body === "string";
    init.body = text ? body : JSON.stringify(body);
    init.headers["Content-Type"] = contentType || (text ? "text/plain" : "application/json");
  }
  const res = await fetch(path, init);
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
