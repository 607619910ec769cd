// The sensor kinds' specs, without their implementations (core/vehicle_spec.h holds them in SensorSpec):
// one alternative per kind, in sensors/sensor_kinds.h's order (which checks that they are the same).
#pragma once

#include <variant>

#include "hadal/sensors/altimeter_spec.h"
#include "hadal/sensors/camera_spec.h"
#include "hadal/sensors/dvl_spec.h"
#include "hadal/sensors/fls_spec.h"
#include "hadal/sensors/force_torque_spec.h"
#include "hadal/sensors/gps_spec.h"
#include "hadal/sensors/imu_spec.h"
#include "hadal/sensors/lbl_spec.h"
#include "hadal/sensors/magnetometer_spec.h"
#include "hadal/sensors/modem_spec.h"
#include "hadal/sensors/multibeam_spec.h"
#include "hadal/sensors/pressure_spec.h"
#include "hadal/sensors/profiler_spec.h"
#include "hadal/sensors/sidescan_spec.h"
#include "hadal/sensors/usbl_spec.h"

namespace hadal::sensors {

using SensorKindSpec = std::variant<PressureSpec, ImuSpec, MagnetometerSpec, GpsSpec, DvlSpec, AltimeterSpec,
                                    ProfilerSpec, CameraSpec, FlsSpec, MultibeamSpec, SidescanSpec, ForceTorqueSpec,
                                    UsblSpec, LblSpec, ModemSpec>;

}  // namespace hadal::sensors
