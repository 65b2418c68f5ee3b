// Listing 25: Dynamic object creation and registration. (C++ of the CBSE framework, not
// GU-DSL: kept for completeness, cleaned of the extraction damage; not parsed by gudsl.)
#define CONSTRUCTOR_FUNCTION(FUNC)                      \
    static const struct FUNC##__ctor__ {                \
        inline FUNC##__ctor__() { FUNC(); }             \
    } FUNC##_ctor_instance_;

#define GENERIC_REGISTER_OBJECT(PluginType, ObjectType, RegisterFunction)                  \
    void RegisterFunction()                                                                \
    {                                                                                      \
        Core::Processing::Interfaces::ConstIObjectPtr sObject = ObjectType::createObject(); \
        PluginType::instance()->RegisterFunction(sObject);                                 \
    }                                                                                      \
    CONSTRUCTOR_FUNCTION(RegisterFunction)

#define REGISTER_OBJECT(PluginType, ObjectType) \
    GENERIC_REGISTER_OBJECT(PluginType, ObjectType, registerObject)

REGISTER_OBJECT(Processing::Plugin::ProcessingPlugin, ComponentClassDefinitions::Sources::Camera)
