// A 422's `field` ("study.case.entry.velocity_fps", "entry.velocity_fps", "constraints.0.equals") shown next to
// the input that holds it: inputs carry data-field paths relative to the study.

/** The input whose data-field best matches a server field name: equal, a prefix of it, or (for names given
 * without their parents, as in "entry.velocity_fps") a suffix. Longest match wins. */
export function inputForField(form, field) {
  if (!field) return null;
  const name = field.replace(/^(body\.)?(study\.)?/, "");
  let best = null, bestLength = -1;
  for (const input of form.querySelectorAll("[data-field]")) {
    const f = input.dataset.field;
    if ((name === f || name.startsWith(f + ".") || f.endsWith("." + name)) && f.length > bestLength) {
      best = input; bestLength = f.length;
    }
  }
  return best;
}

export function clearFieldErrors(form) {
  form.querySelectorAll(".field-error[data-for]").forEach((e) => e.remove());
  form.querySelectorAll("[aria-invalid]").forEach((e) => e.removeAttribute("aria-invalid"));
}

/** The text of an input's label, without its sub-elements ("Velocity, earth-relative (ft/s)"). */
function labelText(input) {
  const label = input.closest("label");
  if (!label) return null;
  return [...label.childNodes].filter((n) => n.nodeType === Node.TEXT_NODE).map((n) => n.textContent).join("").trim() || null;
}

/** The service's message with its field path ("case.entry.velocity_fps: 50 is outside ...") worded by the
 * label a planner sees ("Velocity, earth-relative (ft/s): 50 is outside ..."), pydantic's phrases in the form's
 * words, and an example of what the field takes (its default value, or the hint its HTML placeholder attribute
 * shows in the empty field). */
export function wordedMessage(message, field, input) {
  const label = input && labelText(input);
  let text = formWords(message);
  const example = input && exampleOf(input);
  if (example && (text !== message || /outside the allowed range/.test(text))) text += `; e.g. ${example}`;
  if (!label || !field) return text;
  const name = field.replace(/^(body\.)?/, "");
  for (const path of [name, name.replace(/^study\./, "")]) {
    if (text.startsWith(`${path}: `)) return `${label}: ${text.slice(path.length + 2)}`;
  }
  return text;
}

// pydantic's phrases (its validation errors, "... (got <the input's repr>)") as a planner says them
const got = (g) => (g === "None" || g === undefined ? null : g);
const PHRASES = [
  [/Input should be a valid (number|integer)(?:, ([^(]*?))? \(got (.*?)\)/g, (_, kind, why, g) =>
    got(g) === null ? `a ${kind === "integer" ? "whole " : ""}number is needed`
      : `${g} is not a ${kind === "integer" ? "whole " : ""}number`],
  [/Input should be a finite number \(got (.*?)\)/g, (_, g) => `${g} is not a finite number`],
  [/List should have at least (\d+) items? after validation, not \d+(?: \(got .*?\))?/g, (_, n) =>
    `give at least ${n} value${n === "1" ? "" : "s"}`],
  [/List should have at most (\d+) items? after validation, not (\d+)(?: \(got .*?\))?/g, (_, n, m) =>
    `give at most ${n} values, not ${m}`],
  [/Input should be a valid (?:datetime|date)(?: or date)?[^(]*\(got (.*?)\)/g, (_, g) =>
    got(g) === null ? "a date and time (UTC) is needed" : `${g} is not a date and time (UTC)`],
  [/Input should be (greater|less) than( or equal to)? (\S+?)(?: \(got (.*?)\))?(?=;|$)/g, (_, side, eq, x, g) =>
    `${got(g) ?? "the value"} is not ${eq ? (side === "greater" ? "at least" : "at most") : `${side === "greater" ? "more" : "less"} than`} ${x}`],
  [/Input should be a valid (string|list|boolean)(?: \(got (.*?)\))?/g, (_, kind) =>
    ({ string: "text is needed", list: "a list of values is needed", boolean: "yes or no is needed" })[kind]],
  [/Field required/g, () => "missing"],
];

export function formWords(message) {
  return PHRASES.reduce((text, [pattern, words]) => text.replace(pattern, words), message);
}

/** What the input takes, as its default value or its HTML placeholder attribute (the hint shown in the empty field)
 * shows it; a long list cut to its first three. */
function exampleOf(input) {
  const given = (input.defaultValue || input.getAttribute("placeholder") || "").replace(/^e\.g\.\s*/, "").trim();
  if (!given || input.tagName === "SELECT" || ["checkbox", "radio", "file"].includes(input.type) || given.includes("\n")) return null;
  const items = given.split(/\s*,\s*/);
  return items.length > 3 ? `${items.slice(0, 3).join(", ")}, …` : given;
}

/** Show the message next to the field's input (or in `fallback` when no input holds that field). */
export function showFieldError(form, error, fallback) {
  const input = inputForField(form, error.field);
  if (!input) {
    fallback.textContent = error.message;
    fallback.hidden = false;
    return null;
  }
  const note = document.createElement("span");
  note.className = "field-error";
  note.dataset.for = input.id;
  note.id = `${input.id}-error`;
  note.setAttribute("role", "alert");
  note.textContent = wordedMessage(error.message, error.field, input);
  input.setAttribute("aria-invalid", "true");
  input.setAttribute("aria-describedby", note.id);
  input.insertAdjacentElement("afterend", note);
  input.focus();
  return note;
}
