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
 * label a planner sees ("Velocity, earth-relative (ft/s): 50 is outside ..."). */
export function wordedMessage(message, field, input) {
  const label = input && labelText(input);
  if (!label || !field) return message;
  const name = field.replace(/^(body\.)?/, "");
  for (const path of [name, name.replace(/^study\./, "")]) {
    if (message.startsWith(`${path}: `)) return `${label}: ${message.slice(path.length + 2)}`;
  }
  return message;
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
