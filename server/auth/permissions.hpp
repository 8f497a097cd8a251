#pragma once
// What each role may do: the single table every WebSocket message and REST route is checked against.
#include "server/server_settings.hpp"

namespace labo::server {

enum class Permission {
  Watch,           // video, telemetry, events
  Stop,            // end the mission: hover, then land (anyone watching may)
  CutMotors,       // the emergency stop: the controller has it on top of their role
  RequestControl,  // join the queue; mission commands need control on top
  TakeOver,        // take control from whoever holds it
  ViewSessions,    // GET /api/users, sessions and queue state
  ManagePeople,    // register faces from photos, delete them, choose whom face-follow follows
  EndTurn,         // end a student's turn with a reason
  Administer,      // config, instruments, recordings
};

constexpr bool role_may(Role role, Permission p) {
  switch (p) {
    case Permission::Watch:
    case Permission::Stop:
    case Permission::RequestControl: return true;
    // In a class of thirty viewers one keypress must not drop the drone from a metre: a student
    // cuts the motors only while holding control (RemoteLab checks that).
    case Permission::CutMotors:
    case Permission::TakeOver:
    case Permission::ViewSessions:
    case Permission::ManagePeople:
    case Permission::EndTurn: return role == Role::Teacher || role == Role::Admin;
    case Permission::Administer: return role == Role::Admin;
  }
  return false;
}

}  // namespace labo::server
