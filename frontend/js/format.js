// Numbers for people: thousands separators, a fixed number of decimals, an en dash for nothing.

export function fmt(value, digits = 0) {
  if (value == null || Number.isNaN(value)) return "–";
  const text = Number(value).toLocaleString("en-US", { minimumFractionDigits: digits, maximumFractionDigits: digits });
  return /^-[0.]+$/.test(text) ? text.slice(1) : text; // -0.004 nmi at 0 digits reads "0", not "-0"
}

/** A new element: attributes set as properties or attributes (never parsed as markup), strings as text nodes.
 *  Names and other user text go into the page this way, so that no escaping can be forgotten (issue 15). */
export function el(tag, attributes = {}, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attributes)) {
    if (key === "class") node.className = value;
    else if (key === "style") Object.assign(node.style, value);
    else if (key === "dataset") Object.assign(node.dataset, value);
    else if (key in node && typeof value !== "string") node[key] = value;
    else node.setAttribute(key, value);
  }
  node.append(...children.filter((c) => c != null && c !== ""));
  return node;
}

export function escapeHtml(text) {
  return String(text).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" })[c]);
}
