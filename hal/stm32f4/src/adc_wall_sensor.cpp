// The wall sensors on the MCU: AdcWallSensor on the MCU's bus, instantiated here once (the
// header has the implementation, so the host tests instantiate it on their fakes). An image links
// this object only if its board builds a sensor: none does yet (docs/stm32f4.md, flash).
#include "odocal/hal/stm32f4/adc_wall_sensor.hpp"

#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4 {

template class AdcWallSensor<MemoryBus>;

}  // namespace odocal::hal::stm32f4
