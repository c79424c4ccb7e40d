// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/viewer/portal_dialog.h"

#include "ui/session/file_kinds.h"

#include <filesystem>
#include <gio/gio.h>
#include <libportal/portal.h>

namespace dtf::app {

namespace {

constexpr const char* kPortalName = "org.freedesktop.portal.Desktop";
constexpr int kBusTimeoutMs = 500;

// Whether the bus has `name` now or can start it.
bool busKnows(GDBusConnection* bus, const char* method, const char* name) {
  GError* error = nullptr;
  GVariant* reply =
      g_dbus_connection_call_sync(bus, "org.freedesktop.DBus", "/org/freedesktop/DBus",
                                  "org.freedesktop.DBus", method, name ? g_variant_new("(s)", name) : nullptr,
                                  nullptr, G_DBUS_CALL_FLAGS_NONE, kBusTimeoutMs, nullptr, &error);
  if (!reply) {
    g_clear_error(&error);
    return false;
  }
  bool found = false;
  if (name) {
    gboolean has = FALSE;
    g_variant_get(reply, "(b)", &has);
    found = has;
  } else {
    GVariantIter* names = nullptr;
    const char* n = nullptr;
    g_variant_get(reply, "(as)", &names);
    while (g_variant_iter_loop(names, "&s", &n))
      if (g_strcmp0(n, kPortalName) == 0) found = true;
    g_variant_iter_free(names);
  }
  g_variant_unref(reply);
  return found;
}

// The portal's filter list a(sa(us)): one filter of the target's name patterns.
GVariant* filtersFor(session::FileTarget target) {
  GVariantBuilder patterns;
  g_variant_builder_init(&patterns, G_VARIANT_TYPE("a(us)"));
  for (const auto& p : session::fileTargetPatterns(target))
    g_variant_builder_add(&patterns, "(us)", 0u, p.c_str());
  GVariantBuilder filters;
  g_variant_builder_init(&filters, G_VARIANT_TYPE("a(sa(us))"));
  g_variant_builder_add(&filters, "(s@a(us))", session::fileTargetName(target),
                        g_variant_builder_end(&patterns));
  return g_variant_builder_end(&filters);
}

} // namespace

struct PortalDialog::State {
  XdpPortal* portal = nullptr;
  bool asking = false;
  session::FileTarget target = session::FileTarget::Data;
  std::optional<Answer> answer;
};

namespace {

void answered(GObject* source, GAsyncResult* result, gpointer data) {
  auto* state = static_cast<PortalDialog::State*>(data);
  GError* error = nullptr;
  GVariant* reply = session::isSaveTarget(state->target)
                        ? xdp_portal_save_file_finish(XDP_PORTAL(source), result, &error)
                        : xdp_portal_open_file_finish(XDP_PORTAL(source), result, &error);
  PortalDialog::Answer answer;
  answer.target = state->target;
  if (!reply) {
    if (!g_error_matches(error, G_IO_ERROR, G_IO_ERROR_CANCELLED))
      answer.error = error ? error->message : "no answer";
    g_clear_error(&error);
  } else {
    const char** uris = nullptr;
    if (g_variant_lookup(reply, "uris", "^a&s", &uris) && uris && uris[0]) {
      if (gchar* path = g_filename_from_uri(uris[0], nullptr, nullptr)) {
        answer.path = path;
        g_free(path);
      } else {
        answer.error = std::string("not a local file: ") + uris[0];
      }
    }
    g_free(uris);
    g_variant_unref(reply);
  }
  state->asking = false;
  state->answer = std::move(answer);
}

} // namespace

std::unique_ptr<PortalDialog> PortalDialog::connect() {
  GError* error = nullptr;
  GDBusConnection* bus = g_bus_get_sync(G_BUS_TYPE_SESSION, nullptr, &error);
  if (!bus) {
    g_clear_error(&error);
    return nullptr;
  }
  const bool portal =
      busKnows(bus, "NameHasOwner", kPortalName) || busKnows(bus, "ListActivatableNames", nullptr);
  g_object_unref(bus);
  if (!portal) return nullptr;
  auto state = std::make_unique<State>();
  state->portal = xdp_portal_new();
  if (!state->portal) return nullptr;
  return std::unique_ptr<PortalDialog>(new PortalDialog(std::move(state)));
}

PortalDialog::PortalDialog(std::unique_ptr<State> state) : state_(std::move(state)) {}

PortalDialog::~PortalDialog() {
  // An open question's callback holds the state: let it arrive before the portal goes.
  for (int i = 0; i < 100 && state_->asking; ++i)
    g_main_context_iteration(nullptr, FALSE);
  if (!state_->asking) g_object_unref(state_->portal);
}

bool PortalDialog::ask(session::FileTarget target, const std::string& folder) {
  if (state_->asking) return false;
  state_->asking = true;
  state_->target = target;
  state_->answer.reset();
  const char* title = session::fileTargetTitle(target);
  if (session::isSaveTarget(target)) {
    std::error_code ec;
    const std::string start = folder.empty() ? std::filesystem::current_path(ec).string() : folder;
    xdp_portal_save_file(state_->portal, nullptr, title, nullptr, start.c_str(), nullptr, filtersFor(target),
                         nullptr, nullptr, XDP_SAVE_FILE_FLAG_NONE, nullptr, answered, state_.get());
  } else {
    xdp_portal_open_file(state_->portal, nullptr, title, filtersFor(target), nullptr, nullptr,
                         XDP_OPEN_FILE_FLAG_NONE, nullptr, answered, state_.get());
  }
  return true;
}

void PortalDialog::iterate() {
  while (g_main_context_iteration(nullptr, FALSE)) {
  }
}

std::optional<PortalDialog::Answer> PortalDialog::take() {
  std::optional<Answer> a;
  a.swap(state_->answer);
  return a;
}

} // namespace dtf::app
