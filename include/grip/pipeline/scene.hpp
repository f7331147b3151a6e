#pragma once
/// \file
/// The Scene concept of the haptic pipeline: a contact source for the hand and the object.
/// A Scene provides
///   int hand_contacts(const HandPosture<S>&, const RigidBody<S>& object, HandContacts<S, K>&) const;
///   int obstacle_contacts(const RigidBody<S>& object, ObstacleContactSet<S>&) const;
/// and, if K (its most contacts per phalanx) is not 1, `static constexpr int
/// contacts_per_phalanx = K`. CylinderScene and OctreeScene are Scenes.

#include <type_traits>

namespace grip {
namespace detail {

/// A scene's most hand contacts per phalanx: Scene::contacts_per_phalanx, 1 if it has none.
template <class Scene, class = void>
struct scene_contacts_per_phalanx : std::integral_constant<int, 1> {};
template <class Scene>
struct scene_contacts_per_phalanx<Scene, std::void_t<decltype(Scene::contacts_per_phalanx)>>
    : std::integral_constant<int, Scene::contacts_per_phalanx> {};

}  // namespace detail
}  // namespace grip
