//! BVH skeleton files: parsing, forward kinematics, rotations, keyframe reduction (see issue 5).
