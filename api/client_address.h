// Who sent a request, behind reverse proxies: the peer's address, or, when the peer is
// one of ApiSettings::trusted_proxies, the address its X-Forwarded-For names last that is
// not itself a trusted proxy (proxies append the address they received from, so the
// rightmost entries are the ones our own proxies wrote; anything further left is the
// client's word and can be forged). The answer keys tenants' quotas and the logs, so a
// value that is not an IPv4 or IPv6 address (at most 45 characters of hex digits, dots
// and colons) is never taken from the header.
#pragma once

#include <httplib.h>

#include <string>

#include "api/backend.h"

namespace spheremap::api {

std::string client_address(const ApiSettings& settings, const httplib::Request& request);

}  // namespace spheremap::api
