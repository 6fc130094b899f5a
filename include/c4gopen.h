/* SPDX-License-Identifier: MIT */
/**
 * @file c4gopen.h
 * @brief libc4gopen: the C4G Open real-time protocol, PC side and controller side.
 *
 * INTEGRATION
 *   Include this one header and link libc4gopen.a (or -lc4gopen). The library is
 *   C99, allocation-free and I/O-free: it never calls malloc, stdio, sockets or a
 *   clock. All state lives in structs the caller owns (stack, static or shared
 *   memory); buffers are passed in as (pointer, length/capacity).
 *
 * LAYERS (one header each; this umbrella includes them all)
 *   c4gopen_base.h     version, the one status type, c4g_strerror
 *   c4gopen_wire.h     packets, initialization packet, mode vocabulary, NUM policy,
 *                      datagram classifier, session (the PC end)
 *   c4gopen_ctrl.h     the controller end: handshake driver, reply checks, deadlines
 *   c4gopen_engine.h   engine: mode state machines, packet rules, safety
 *                      filter, kinematics, soft control switching, monitoring
 *   c4gopen_loop.h     the PC-side loop object: session + engine in one
 *   c4gopen_cell.h     the cell line protocol (usable alone: needs only the base)
 *   c4gopen_canopen.h  CANopen master and DS402 drives (usable alone: needs only the base)
 *   c4gopen_dyn.h      rigid-body dynamics of a serial arm: Newton-Euler and its regressor
 *                      (usable alone: needs only the base)
 *
 *   A PC-side real-time loop (c4gopen_loop.h):
 *     n = recvfrom(...);
 *     c4g_loop_rx(&lp, buf, n, now(), &from, &ev);       decode, init, control step
 *     if (ev.cmd != NULL) { ... fill the fields the mode needs ... }
 *     c4g_loop_reply(&lp, out, sizeof out, &len, &rep);   safety filter, encode
 *     sendto(..., out, len, ...);  c4g_loop_sent(&lp, now());
 *
 * THREADING
 *   Not thread-safe: one context per loop. No call blocks; every call is O(packet
 *   size) with loop bounds fixed by protocol constants, never by input values.
 *
 * ERRORS
 *   Every function that can fail returns a c4g_status_t (c4gopen_base.h): 0 is success,
 *   negative values are errors. c4g_strerror() gives a short constant string. Decoders
 *   fill an optional diagnostic naming the byte offset, field, arm/axis and raw value.
 */
#ifndef C4GOPEN_H
#define C4GOPEN_H

#include "c4gopen_base.h"
#include "c4gopen_wire.h"
#include "c4gopen_ctrl.h"
#include "c4gopen_engine.h"
#include "c4gopen_loop.h"
#include "c4gopen_cell.h"
#include "c4gopen_canopen.h"
#include "c4gopen_dyn.h"

#endif /* C4GOPEN_H */
