// The robot's flash store: FlashStore on the MCU's bus, instantiated here once (the header has
// the implementation, so the host tests instantiate it on their flash model).
#include "odocal/hal/stm32f4/flash_store.hpp"

#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4 {

template class FlashStore<MemoryBus>;

}  // namespace odocal::hal::stm32f4
