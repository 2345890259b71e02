// Reads the events of a text/event-stream response, calling onEvent(name, data, id) for each
// whose data is JSON; resolves when the stream ends.
async function readEvents(res, onEvent) {
  const reader = res.body.pipeThrough(new TextDecoderStream()).getReader();
  let buffer = "";
  for (;;) {
    const { value, done } = await reader.read();
    if (done) return;
    buffer += value.replace(/\r\n/g, "\n");
    let end;
    while ((end = buffer.indexOf("\n\n")) >= 0) {
      const block = buffer.slice(0, end);
      buffer = buffer.slice(end + 2);
      let event = "message", text = "", id = "";
      for (const line of block.split("\n")) {
        if (!line || line.startsWith(":")) continue;
        const colon = line.indexOf(":");
        const field = colon < 0 ? line : line.slice(0, colon);
        let v = colon < 0 ? "" : line.slice(colon + 1);
        if (v.startsWith(" ")) v = v.slice(1);
        if (field === "event") event = v;
        else if (field === "data") text += (text ? "\n" : "") + v;
        else if (field === "id") id = v;
      }
      let data;
      try { data = JSON.parse(text); } catch { continue; }
      onEvent(event, data, id);
    }
  }
}

// GET an event stream (like EventSource, but through the page's fetch, which carries the API
// key). Resolves to the response's status once the stream ends (or at once when it is not a
// stream); rejects when `signal` aborts.
export async function getStream(url, { signal, onEvent }) {
  const res = await fetch(url, { headers: { Accept: "text/event-stream" }, signal });
  if (!(res.headers.get("Content-Type") || "").startsWith("text/event-stream")) return res.status;
  await readEvents(res, onEvent);
  return res.status;
}

// POST a JSON body with "stream": true and read the Server-Sent Events of the answer (EventSource
// only does GET). onEvent(name, data) is called for each event as it arrives. Resolves to
// {status, data}: the `done` event's answer with status 200, the `error` event's with its
// status, or the JSON of a request refused before streaming began. Rejects when `signal` aborts
// (which closes the connection: the server cancels the job).
export async function postStream(url, body, { signal, onEvent }) {
  const res = await fetch(url, {
    method: "POST",
    headers: { "Content-Type": "application/json", Accept: "text/event-stream" },
    body: JSON.stringify({ ...body, stream: true }),
    signal,
  });
  const type = res.headers.get("Content-Type") || "";
  if (!type.startsWith("text/event-stream")) {
    let data = null;
    try { data = await res.json(); } catch { /* not JSON */ }
    return { status: res.status, data: data || { error: { code: `http_${res.status}`, message: res.statusText } } };
  }
  let final = null;
  await readEvents(res, (event, data) => {
    onEvent(event, data);
    if (event === "done") final = { status: 200, data };
    else if (event === "error") final = { status: data.status || 500, data };
  });
  return final || { status: 0, data: { error: { code: "stream_ended", message: "the connection closed before the answer came" } } };
}
