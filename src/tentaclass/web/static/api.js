// JSON API client: every call resolves to the parsed body or throws an Error with the
// server's message (the "detail" of a 4xx/5xx answer).

async function parse(response) {
  let body = null;
  try {
    body = await response.json();
  } catch (e) {
    body = null;
  }
  if (!response.ok) {
    const detail = body && typeof body.detail === "string" ? body.detail : response.statusText;
    throw new Error(detail || `request failed (${response.status})`);
  }
  return body;
}

export async function post(path, payload) {
  const r = await fetch(path, {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify(payload),
  });
  return parse(r);
}

export async function upload(path, file) {
  const form = new FormData();
  form.append("file", file);
  return parse(await fetch(path, { method: "POST", body: form }));
}

export async function get(path) {
  return parse(await fetch(path));
}

export async function del(path) {
  return parse(await fetch(path, { method: "DELETE" }));
}
