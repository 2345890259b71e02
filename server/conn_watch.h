// Tells whether an HTTP client is still connected, for cancelling its solver job when it goes
// away. cpp-httplib 0.11 gives handlers neither the socket nor a disconnect check, so this reads
// the kernel's TCP table (/proc/net/tcp and tcp6, Linux): the connection is identified by the
// server's local port and the client's port; once it is no longer ESTABLISHED (the peer closed
// it, or it is gone), the client has left.
#pragma once

namespace ctb::server {

// True while a TCP connection from remote_port to local_port is in state ESTABLISHED.
// False when it is in another state or not listed.
bool ClientConnected(int local_port, int remote_port);

}  // namespace ctb::server
