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
  const reader = res.body.pipeThrough(new TextDecoderStream()).getReader();
  let buffer = "";
  let final = null;
  for (;;) {
    const { value, done } = await reader.read();
    if (done) break;
    buffer += value.replace(/\r\n/g, "\n");
    let end;
    while ((end = buffer.indexOf("\n\n")) >= 0) {
      const block = buffer.slice(0, end);
      buffer = buffer.slice(end + 2);
      let event = "message", text = "";
      for (const line of block.split("\n")) {
        if (!line || line.startsWith(":")) continue;
        const colon = line.indexOf(":");
        const field = colon < 0 ? line : line.slice(0, colon);
        let v = colon < 0 ? "" : line.slice(colon + 1);
        if (v.startsWith(" ")) v = v.slice(1);
        if (field === "event") event = v;
        else if (field === "data") text += (text ? "\n" : "") + v;
      }
      let data;
      try { data = JSON.parse(text); } catch { continue; }
      onEvent(event, data);
      if (event === "done") final = { status: 200, data };
      else if (event === "error") final = { status: data.status || 500, data };
    }
  }
  return final || { status: 0, data: { error: { code: "stream_ended", message: "the connection closed before the answer came" } } };
}
